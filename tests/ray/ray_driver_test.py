#!/usr/bin/env python3
"""The Ray driver (tools/ray/vkpath_ray.py) on a local two-CPU cluster.

    ray_driver_test.py --vkpath BUILD/vkpath --venv BUILD/ray-venv --scene CBspheres.dae

CBspheres in 4 chunks, CPU tasks on lavapipe, must equal the one-process
render: relMSE (vkpath compare) at most 1e-12. The parts are the same samples
by construction and the merge adds their float means in double, so each pixel
is within 8 float ulps of the single render (2^-20 relative, the bound of
tests/cli/merge_test.cpp); a squared relative error of (2^-20)^2 = 9.1e-13 per
pixel bounds the mean, while two renders of different seeds differ by about
1e-2. First on the local cluster the driver starts, with one task's Ray worker
killed (SIGKILL) while its vkpath runs: the driver must say it retries and the
image must still be equal. Then the driver joins a cluster that `ray start
--head` started apart from it (`--address`, as on several machines), nothing
killed: equal again. (Each cluster's start-up is most of the test's time, so
the plain local run is not repeated: the killed run takes that path too.)

Ray comes from PyPI into --venv (made once, kept in the build folder). Exit
code 77 (CTest's skip) only when PyPI cannot be reached or the scene is absent
(the assignment's scene folder, VKPATH_SCENES_DIR); any other failure is a
failure.
"""
import argparse
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DRIVER = os.path.join(HERE, "..", "..", "tools", "ray", "vkpath_ray.py")
RELMSE_BOUND = 1e-12
SIZE = ["-d", "80x60"]
SPP = "16"


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def pypi_reachable():
    try:
        socket.create_connection(("pypi.org", 443), timeout=10).close()
        return True
    except OSError:
        return False


def ensure_venv(venv):
    python = os.path.join(venv, "bin", "python")
    if os.path.exists(python) and subprocess.run([python, "-c", "import ray"], capture_output=True).returncode == 0:
        return python
    if not os.path.exists(python):
        subprocess.run([sys.executable, "-m", "venv", venv], check=True)
    pip = subprocess.run([python, "-m", "pip", "install", "-q", "ray>=2.10"], capture_output=True, text=True)
    if pip.returncode != 0:
        if not pypi_reachable():
            print("SKIPPED: PyPI cannot be reached, so the Ray package cannot be installed "
                  f"(pip: {pip.stderr.strip().splitlines()[-1] if pip.stderr.strip() else pip.returncode})")
            sys.exit(77)
        fail(f"pip install ray failed although PyPI answers:\n{pip.stderr}")
    return python


def relmse(vkpath, a, b):
    r = subprocess.run([vkpath, "compare", a, b, "--json"], capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"vkpath compare {a} {b}: {r.stderr}")
    return json.loads(r.stdout)["overall"]["relMse"]


def expect_equal(vkpath, image, whole, what):
    """Fails unless `image` is within RELMSE_BOUND of the one-process render."""
    error = relmse(vkpath, image, whole)
    print(f"{what}: relMSE {error:.3g} against the one-process render")
    if not error <= RELMSE_BOUND:
        fail(f"{what}: relMSE {error} > {RELMSE_BOUND}")


def chunk_processes():
    """(pid, parent pid) of each running vkpath of a driver task (its -o is in a vkpath-chunk- folder)."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            args = open(f"/proc/{pid}/cmdline", "rb").read().split(b"\0")
            if len(args) > 1 and args[1] == b"render" and any(b"/vkpath-chunk-" in a for a in args):
                stat = open(f"/proc/{pid}/stat").read()
                found.append((int(pid), int(stat.rsplit(")", 1)[1].split()[1])))
        except OSError:
            continue
    return found


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--vkpath", required=True)
    p.add_argument("--venv", required=True)
    p.add_argument("--scene", required=True)
    args = p.parse_args()
    if not os.path.isfile(args.scene):
        print(f"SKIPPED: the assignment's scene {args.scene} is absent (set the CMake variable "
              "VKPATH_SCENES_DIR to the folder holding scotty3d/; README.md, \"Scenes\")")
        sys.exit(77)
    python = ensure_venv(args.venv)
    work = tempfile.mkdtemp(prefix="vkpath-ray-test-")
    try:
        run_tests(args, python, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def run_tests(args, python, work):
    whole = os.path.join(work, "whole.exr")
    r = subprocess.run([args.vkpath, "render", args.scene, *SIZE, "-s", SPP, "-o", whole], capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"the one-process render: {r.stderr}")
    driver = [python, DRIVER, args.scene, "-s", SPP, "--chunks", "4", "--num-cpus", "2", "--vkpath", args.vkpath]

    # On the driver's own local cluster, one worker killed while its chunk renders.
    retried = os.path.join(work, "retried.exr")
    log = open(os.path.join(work, "driver.log"), "w+")
    run = subprocess.Popen(driver + ["-o", retried, "--", *SIZE], stdout=subprocess.DEVNULL, stderr=log)
    killed = None
    deadline = time.monotonic() + 120
    while killed is None and run.poll() is None and time.monotonic() < deadline:
        for pid, worker in chunk_processes():
            os.kill(worker, signal.SIGKILL)  # the Ray worker running the task, not vkpath itself
            killed = worker
            break
        time.sleep(0.01)
    try:
        code = run.wait(timeout=300)
    except subprocess.TimeoutExpired:
        run.kill()
        fail("the driver did not finish within 300 s after a worker was killed")
    log.seek(0)
    text = log.read()
    if killed is None:
        fail(f"no chunk's vkpath was seen running to kill its worker:\n{text}")
    if code != 0:
        fail(f"the driver exited with {code} after worker {killed} was killed:\n{text}")
    if "retrying" not in text:
        fail(f"worker {killed} was killed but the driver did not say it retried:\n{text}")
    print(text, end="")
    expect_equal(args.vkpath, retried, whole, "4 chunks, a worker killed, its chunk retried")

    # The same driver joining a cluster started apart from it, as on several
    # machines (`ray start --head` here, `--address` for the driver).
    ray = os.path.join(os.path.dirname(python), "ray")
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    start = subprocess.run([ray, "start", "--head", "--num-cpus", "2", f"--port={port}", "--include-dashboard=false",
                            "--disable-usage-stats"], capture_output=True, text=True)
    if start.returncode != 0:
        fail(f"ray start --head: {start.stderr}")
    try:
        joined = os.path.join(work, "joined.exr")
        r = subprocess.run([python, DRIVER, args.scene, "-s", SPP, "--chunks", "4", "--address", f"127.0.0.1:{port}",
                            "--vkpath", args.vkpath, "-o", joined, "--", *SIZE], capture_output=True, text=True,
                           timeout=300)
    finally:
        subprocess.run([ray, "stop", "--force"], capture_output=True)
    if r.returncode != 0:
        fail(f"the driver with --address exited with {r.returncode}:\n{r.stderr}")
    expect_equal(args.vkpath, joined, whole, "on a cluster started by ray start, joined with --address")
    print("PASS")


if __name__ == "__main__":
    main()
