# The validation ladder at the sweep's preset (results/validation/<preset>/, shared by all
# sweeps at that preset): metrics against theory, Table II and the experiments, and figures.


rule validation_summary:
    input:
        **{target: validation_nc(target) for target in VALIDATION},
    output:
        csv="results/validation/{preset}/validation.csv",
        html=report(
            "results/validation/{preset}/validation.html",
            caption="../report/validation.rst",
            category="Validation",
            labels={"preset": "{preset}", "table": "metrics"},
        ),
    params:
        runs={target: list(runs) for target, runs in VALIDATION.items()},
        window=lambda w: SWEEP_CFG["preset_settings"]["wave_tank"]["window"],
        data_dir=str(DATA_DIR),
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/validation_summary.log",
    script:
        "../scripts/validation_summary.py"


rule validation_figure_wave_tank:
    input:
        nc=validation_nc("wave_tank"),
    output:
        png=report(
            "results/validation/{preset}/figures/fig07_wave_tank.png",
            caption="../report/fig07_wave_tank.rst",
            category="Validation",
            labels={"preset": "{preset}", "figure": "fig07_wave_tank"},
        ),
    params:
        window=SWEEP_CFG["preset_settings"]["wave_tank"]["window"],
        data_dir=str(DATA_DIR),
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/figures/fig07_wave_tank.log",
    script:
        "../scripts/fig_wave_tank.py"


rule validation_figure_sloshing:
    input:
        nc=validation_nc("sloshing"),
    output:
        png=report(
            "results/validation/{preset}/figures/fig_sloshing.png",
            caption="../report/fig_sloshing.rst",
            category="Validation",
            labels={"preset": "{preset}", "figure": "fig_sloshing"},
        ),
    params:
        window=SWEEP_CFG["preset_settings"]["wave_tank"]["window"],
        data_dir=str(DATA_DIR),
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/figures/fig_sloshing.log",
    script:
        "../scripts/fig_sloshing.py"


rule validation_figure_decay:
    input:
        nc=validation_nc("decay"),
    output:
        png=report(
            "results/validation/{preset}/figures/fig_decay.png",
            caption="../report/fig_decay.rst",
            category="Validation",
            labels={"preset": "{preset}", "figure": "fig_decay"},
        ),
    params:
        window=SWEEP_CFG["preset_settings"]["wave_tank"]["window"],
        data_dir=str(DATA_DIR),
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/figures/fig_decay.log",
    script:
        "../scripts/fig_decay.py"


rule validation_figure_floating_box:
    input:
        nc=validation_nc("floating_box"),
    output:
        png=report(
            "results/validation/{preset}/figures/fig_floating_box.png",
            caption="../report/fig_floating_box.rst",
            category="Validation",
            labels={"preset": "{preset}", "figure": "fig_floating_box"},
        ),
    params:
        window=SWEEP_CFG["preset_settings"]["wave_tank"]["window"],
        data_dir=str(DATA_DIR),
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/figures/fig_floating_box.log",
    script:
        "../scripts/fig_floating_box.py"


rule validation_figure_dam_break:
    input:
        nc=validation_nc("dam_break"),
    output:
        png=report(
            "results/validation/{preset}/figures/fig_dam_break.png",
            caption="../report/fig_dam_break.rst",
            category="Validation",
            labels={"preset": "{preset}", "figure": "fig_dam_break"},
        ),
    params:
        window=SWEEP_CFG["preset_settings"]["wave_tank"]["window"],
        data_dir=str(DATA_DIR),
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/figures/fig_dam_break.log",
    script:
        "../scripts/fig_dam_break.py"
