# One engine run per case: a case file (the built-in case plus this run's values), then
# `sph run`. The engine keeps checkpoints in OUTPUT.ckpt/ beside the output and resumes from
# them when the same run is started again (after a kill, a pre-emption, a time limit): the
# checkpoint folder is deliberately not an output, so that snakemake does not delete it
# when it reruns an incomplete job (`--rerun-incomplete`, set in the default profile). A
# checkpoint left by a run of other parameters is refused by the engine (exit status 2);
# the run then starts over from t = 0. A run that blows up (exit status 3) has written its
# output up to then, marked with its status (the step, time and cause): that is the case's
# result, so the job succeeds with a warning in its log, the sweep is gathered with the
# case NaN after its end, and the findings that need it later are not determinable
# (sph.study.sweeps.gather, sph.study.findings). Running it again would blow up again.

#
# The ship cases that differ in the opening alone (Table I cases 1-5) are the same run until
# the opening appears at t1: one run of the intact ship to just before t1 (`predamage_*`,
# keeping its checkpoints) is shared, and each of these cases starts from its last
# checkpoint (`sph run --start-from`), to the same numbers as from t = 0
# (sph.study.sweeps.predamage_runs).

# The shells wait for the run whatever signal comes: a job stopped as a whole (a cluster's
# time limit, Ctrl-C: SIGTERM or SIGINT to every process of the job) stops the run, which
# writes a checkpoint and its output and exits with 4, and only then the job; a shell that
# died first let Snakemake clean the job up while the run was still writing its output,
# and the next call took that partial series for the case's result. A trapped signal is
# reset to the default in `sph run` itself, and in the subshell, hence the second trap.
SPH_RUN = (
    "trap : TERM INT; ( trap : TERM INT; s=0; sph run {input.case:q} -o {output.nc:q}"
    " --threads {threads} --no-progress {params.start} || s=$?;"
    " if [ $s -eq 2 ] && [ -d {output.nc:q}.ckpt ]; then"
    " echo 'checkpoint of other parameters: starting over'; s=0; sph run {input.case:q}"
    " -o {output.nc:q} --threads {threads} --no-progress --restart {params.start} || s=$?; fi;"
    " if [ $s -eq 3 ]; then echo 'warning: the run blew up (above); its output up to then"
    " is the result of this case, marked with its status; the findings that need it"
    " later are not determinable'; s=0; fi; exit $s ) > {log:q} 2>&1"
)


rule calibrate_wavemaker:
    # the flap angle that gives the ship's wave amplitude at its position (a wave-tank run
    # with the ship's numerics and no ship, repeated until within 2 %; sph/study/calibration.py)
    output:
        "results/{sweep}/calibration/{wave}.json",
    params:
        document=calibration_document,
        configuration=calibration_digest,
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/calibration/{wave}.log",
    benchmark:
        "results/{sweep}/benchmarks/calibration/{wave}.tsv"
    threads: 1
    priority: SHIP_PRIORITY + 1
    script:
        "../scripts/calibrate_wavemaker.py"


rule case_file:
    input:
        calibration=calibration_of,
    output:
        "results/{sweep}/cases/{case}.yaml",
    params:
        document=ship_document,
        configuration=ship_digest,
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/case_file/{case}.log",
    localrule: True
    priority: SHIP_PRIORITY
    script:
        "../scripts/case_file.py"


rule predamage_case_file:
    input:
        calibration=predamage_calibration,
    output:
        "results/{sweep}/predamage/{predamage}.yaml",
    params:
        document=predamage_document,
        configuration=predamage_digest,
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/case_file/{predamage}.log",
    localrule: True
    priority: SHIP_PRIORITY + 1
    script:
        "../scripts/case_file.py"


rule simulate_predamage:
    # the run to t1 that the cases differing in the opening alone share; its checkpoints
    # (OUTPUT.ckpt/, run.keep_checkpoints) are what they start from
    input:
        case="results/{sweep}/predamage/{predamage}.yaml",
    output:
        nc="results/{sweep}/predamage/{predamage}.nc",
    params:
        start="",
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/simulate/{predamage}.log",
    benchmark:
        "results/{sweep}/benchmarks/simulate/{predamage}.tsv"
    threads: 1
    priority: SHIP_PRIORITY + 1
    shell:
        SPH_RUN


rule simulate_case:
    input:
        case="results/{sweep}/cases/{case}.yaml",
        predamage=predamage_of,
    output:
        nc="results/{sweep}/cases/{case}.nc",
    params:
        start=start_option,
    conda:
        "../envs/sph.yaml"
    log:
        "results/{sweep}/logs/simulate/{case}.log",
    benchmark:
        "results/{sweep}/benchmarks/simulate/{case}.tsv"
    threads: 1
    priority: SHIP_PRIORITY
    shell:
        SPH_RUN


rule validation_case_file:
    output:
        "results/validation/{preset}/{target}/{run}.yaml",
    params:
        document=validation_document,
        configuration=validation_digest,
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/case_file/{target}/{run}.log",
    localrule: True
    priority: validation_priority
    script:
        "../scripts/case_file.py"


rule simulate_validation:
    input:
        case="results/validation/{preset}/{target}/{run}.yaml",
    output:
        nc="results/validation/{preset}/{target}/{run}.nc",
    conda:
        "../envs/sph.yaml"
    log:
        "results/validation/{preset}/logs/simulate/{target}/{run}.log",
    params:
        start="",
    benchmark:
        "results/validation/{preset}/benchmarks/simulate/{target}/{run}.tsv"
    threads: 1
    priority: validation_priority
    shell:
        SPH_RUN
