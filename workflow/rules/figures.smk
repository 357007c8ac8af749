# The paper's figures (Figs. 10, 12-15, 17-19, 21-23) drawn from the sweep dataset, each for
# the group of cases the paper compares; an overview of every case; and, for a sweep over wave
# frequency, the ship's roll and heave response against omega.


rule ship_figure:
    input:
        nc="results/{sweep}/{sweep}.nc",
    output:
        png=report(
            "results/{sweep}/figures/{figure}.png",
            caption="../report/ship_figure.rst",
            category="Sweep {sweep}",
            labels=lambda w: {"group": SHIP_FIGURES[w.figure][0], "figure": w.figure},
        ),
    params:
        cases=lambda w: GROUPS[SHIP_FIGURES[w.figure][0]],
        group=lambda w: SHIP_FIGURES[w.figure][0],
        series=lambda w: SHIP_FIGURES[w.figure][1],
        t2_periods=SWEEP_CFG["t2_periods"],
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/figures/{figure}.log",
    script:
        "../scripts/fig_ship.py"


rule overview_figure:
    input:
        nc="results/{sweep}/{sweep}.nc",
    output:
        png=report(
            "results/{sweep}/figures/overview.png",
            caption="../report/overview.rst",
            category="Sweep {sweep}",
            labels={"group": "all cases", "figure": "overview"},
        ),
    params:
        cases=list(CASES),
        group="all",
        series=["roll", "heave", "flood_ratio", "W2"],
        t2_periods=SWEEP_CFG["t2_periods"],
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/figures/overview.log",
    script:
        "../scripts/fig_ship.py"


rule rao_figure:
    # roll amplitude / kA and heave amplitude / A against omega (sph/study/response.py); only
    # for sweeps that vary omega (rao_outputs in common.smk)
    input:
        nc="results/{sweep}/{sweep}.nc",
    output:
        png=report(
            "results/{sweep}/figures/rao.png",
            caption="../report/rao_figure.rst",
            category="Sweep {sweep}",
            labels={"group": "wave frequency", "figure": "rao"},
        ),
        csv="results/{sweep}/rao.csv",
    params:
        t2_periods=SWEEP_CFG["t2_periods"],
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/figures/rao.log",
    script:
        "../scripts/fig_rao.py"
