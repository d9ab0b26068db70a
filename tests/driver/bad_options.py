#!/usr/bin/env python3
"""Bad options on the command line give one clear error each: `fdem check SCENE OPTION VALUE`
exits with status 1 on every rank (no crash, no MPI abort, no hang: 120 s a run) and prints
`fdem: error: ...` once, naming the option and what is wrong with its value. (The same options
in a scene's `petsc:` string are tests/driver/bad/petsc_*.yaml.)

  bad_options.py MPIEXEC NP FDEM SCENE.yaml
"""
import os, subprocess, sys, tempfile

mpiexec, np, fdem, scene = sys.argv[1], sys.argv[2], sys.argv[3], os.path.abspath(sys.argv[4])
work = tempfile.mkdtemp(prefix="fdem_bad_options_")
missing = os.path.join(work, "missing.h5")
# (options, text the error must contain)
cases = [
    (["-ts_max_steps", "4294967297"], "-ts_max_steps 4294967297: beyond the integers this build counts"),
    (["-ts_max_steps", "-5"], "-ts_max_steps -5: give the step number to stop at, 0 or more"),
    (["-fdem_insert_every", "99999999999999999999"], "-fdem_insert_every 99999999999999999999: beyond the integers"),
    (["-fdem_balance_gain_limit", "abc"], "-fdem_balance_gain_limit abc: Input string abc has no numeric value"),
    (["-fdem_balance_gain_limit", "-1"], "-fdem_balance_gain_limit -1.: give a fraction >= 0"),
    (["-fdem_progress", "yes2"], "-fdem_progress yes2: Unknown logical value"),
    (["-fdem_advise_strain", "-1"], "-fdem_advise_strain -1.: give a strain > 0"),
    (["-fdem_advise_strain", "abc"], "-fdem_advise_strain abc: Input string abc has no numeric value"),
    (["-fdem_rigid_gravity", "0,0,-9.81,1"], "-fdem_rigid_gravity takes three numbers gx,gy,gz; got more"),
    (["-fdem_deformable_gravity", "nan,0,0"], "-fdem_deformable_gravity nan.,0.,0.: give finite numbers"),
    (["-ts_init_time", "0"], "-ts_init_time: a run starts at t = 0"),
    (["-ts_dt", "0"], "the time step 0. s (-ts_dt) must be positive and finite"),
    (["-ts_dt", "nan"], "the time step nan. s (-ts_dt) must be positive and finite"),
    (["-ts_max_time", "-1"], "the run's end t = -1. s (-ts_max_time) must be finite and after its start"),
    (["-ts_max_time", "inf"], "the run's end t = inf. s (-ts_max_time) must be finite"),
    (["-restart", missing], f"-restart {missing}: "),
    (["-restart", work], f"-restart {work}: not a file"),
    (["-restart", scene], f"-restart {scene}: not an HDF5 file"),
]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
failed = 0
for opts, want in cases:
    cmd = [mpiexec, "--oversubscribe", "-n", np, fdem, "check", scene, "-fdem_progress", "0"] + opts
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env, cwd=work)
        out = r.stdout + r.stderr
        errors = [l for l in out.splitlines() if l.startswith("fdem: error: ")]
        bad = [s for s in ("MPI_ABORT", "Segmentation", "signal", "Traceback", "PETSC ERROR") if s in out]
        ok = r.returncode == 1 and len(errors) == 1 and want in errors[0] and not bad
        why = "" if ok else f"exit {r.returncode}, {len(errors)} error lines, {bad or ''}\n{out[-1500:]}"
    except subprocess.TimeoutExpired:
        ok, why = False, "hung (no exit within 120 s)"
    print(f"{'ok  ' if ok else 'FAIL'} {' '.join(opts)}: {errors[0] if ok else why}")
    failed += not ok
print(f"{len(cases) - failed} of {len(cases)} bad options rejected as expected")
if not failed:
    os.rmdir(work)
sys.exit(1 if failed else 0)
