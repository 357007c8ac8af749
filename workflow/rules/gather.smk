# The sweep dataset (one netCDF file with a `case` dimension) and the paper's findings
# measured on it.


rule gather:
    input:
        nc=expand("results/{{sweep}}/cases/{case}.nc", case=list(CASES)),
    output:
        nc="results/{sweep}/{sweep}.nc",
    params:
        cases=list(CASES.values()),
        attrs=sweep_attrs(),
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/gather.log",
    script:
        "../scripts/gather.py"


rule findings:
    input:
        nc="results/{sweep}/{sweep}.nc",
    output:
        csv="results/{sweep}/findings.csv",
        md="results/{sweep}/findings.md",
        spectra="results/{sweep}/spectra.csv",
        html=report(
            "results/{sweep}/findings.html",
            caption="../report/findings.rst",
            category="Findings",
            labels={"sweep": "{sweep}", "table": "paper's findings"},
        ),
    params:
        groups=GROUPS,
        t2_periods=SWEEP_CFG["t2_periods"],
        title=SWEEP_CFG["title"],
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/findings.log",
    script:
        "../scripts/findings.py"
