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


rule validation_figure:
    # one rule for every validation figure: the figure's record in VALIDATION_FIGURES (from
    # sph.study.validation.TARGETS) names the target whose runs it draws and its script
    input:
        nc=lambda w: validation_nc(VALIDATION_FIGURES[w.figure][0]),
    output:
        png=report(
            "results/validation/{preset}/figures/{figure}.png",
            caption="../report/validation_figure.rst",
            category="Validation",
            labels={"preset": "{preset}", "figure": "{figure}"},
        ),
    params:
        target=lambda w: VALIDATION_FIGURES[w.figure][0],
        script=lambda w: VALIDATION_FIGURES[w.figure][1],
        window=SWEEP_CFG["preset_settings"]["wave_tank"]["window"],
        data_dir=str(DATA_DIR),
    wildcard_constraints:
        figure="|".join(re.escape(name) for name in VALIDATION_FIGURES),
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/figures/{figure}.log",
    script:
        "../scripts/{params.script}.py"
