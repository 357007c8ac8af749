# The paper's figures (Figs. 10, 12-15, 17-19, 21-23) drawn from the sweep dataset, each for
# the group of cases the paper compares; an overview of every case.


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
