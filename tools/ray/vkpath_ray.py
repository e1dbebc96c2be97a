#!/usr/bin/env python3
"""Render one image across a Ray cluster: sample chunks as Ray tasks, merged.

    python3 tools/ray/vkpath_ray.py SCENE -o OUT.exr -s SPP [--chunks N | --chunk-spp K]
        [--address ADDR] [--vkpath PATH] [--num-cpus N] [--cpus-per-task N]
        [--gpus-per-task N] [--retries N] [--aov variance] [-- RENDER FLAGS...]

The render's samples 0..SPP-1 are cut into chunks (FIRST:COUNT); each chunk is
one Ray task that runs `vkpath render --samples FIRST:COUNT` on whichever node
Ray gives it and returns the part's EXR bytes (no shared folder is needed for
the outputs). A task asks for one GPU where the cluster has GPUs, and for
--cpus-per-task CPUs otherwise (lavapipe then gets as many threads). A chunk
whose task fails (vkpath exits 1 or is killed, or Ray loses the worker or its
node) is resubmitted, up to --retries times; a chunk that vkpath refuses as
bad input (exit code 2) ends the render at once with vkpath's own line.
Progress goes to stderr, one line per chunk. The parts are merged with
`vkpath merge`, which checks that they are one render's disjoint, gapless
ranges: random numbers are keyed by (pixel, sample index, seed), so the result
equals the one-process render up to the rounding of the parts' float means
(tests/cli/merge_test.cpp bounds it).

Without --address, Ray starts on this machine (ray.init()); with one, the
driver joins that cluster (`ray start --head` on one node, `ray start
--address HEAD:6379` on the others; Ray 2.59 and later make a token for
that, ~/.ray/auth_token, which the other nodes and this driver need too).
The scene (and what it refers to) and the vkpath executable must be at the
same paths on every node. Exit codes:
0; 2 for bad input (ours or vkpath's); 1 when a chunk still fails after its
retries or Ray cannot start.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

FORBIDDEN = {"-o", "-w", "--output", "-s", "--spp", "--samples", "--png", "--checkpoint", "--resume",
             "--time-budget", "--aov"}


class BadInput(Exception):
    """vkpath refused its input (exit code 2): retrying cannot help."""


def chunk_ranges(spp, chunks=None, chunk_spp=None):
    """Disjoint FIRST:COUNT ranges covering samples 0..spp-1, as equal as they can be."""
    if chunk_spp:
        return [(first, min(chunk_spp, spp - first)) for first in range(0, spp, chunk_spp)]
    chunks = min(chunks, spp)
    ranges, first = [], 0
    for i in range(chunks):
        count = spp // chunks + (1 if i < spp % chunks else 0)
        ranges.append((first, count))
        first += count
    return ranges


def vulkan_device_index(vkpath, gpu_id):
    """vkpath's index (`vkpath info`) of the node's GPU number `gpu_id` as Ray numbers them.

    Ray numbers a node's GPUs as CUDA does; Vulkan lists the same GPUs, for one
    vendor, in PCI order, which is CUDA's with CUDA_DEVICE_ORDER=PCI_BUS_ID
    (not checked on a multi-GPU node: none was at hand). CPU devices (lavapipe)
    are left out of the count.
    """
    import json

    info = json.loads(subprocess.run([vkpath, "info", "--json"], capture_output=True, text=True, check=True).stdout)
    gpus = [d["index"] for d in info["devices"] if d["type"] in ("discrete", "integrated")]
    return gpus[gpu_id % len(gpus)] if gpus else info["chosen"]["index"]


def render_chunk(vkpath, scene, first, count, flags, aov, threads):
    """One part: runs vkpath in a private folder and returns its EXR bytes (and its variance AOV)."""
    import ray  # on the worker

    work = tempfile.mkdtemp(prefix="vkpath-chunk-")
    try:
        out = os.path.join(work, "part.exr")
        command = [vkpath, "render", scene, "--samples", f"{first}:{count}", "-o", out] + flags
        if aov:
            command += ["--aov", "variance"]
        env = dict(os.environ)
        gpus = ray.get_gpu_ids()
        if gpus:
            env["VKPATH_DEVICE_INDEX"] = str(vulkan_device_index(vkpath, int(gpus[0])))
        elif threads:
            env["LP_NUM_THREADS"] = str(threads)  # lavapipe's threads: the CPUs Ray gave the task
        started = time.monotonic()
        result = subprocess.run(command, env=env, capture_output=True, text=True)
        seconds = time.monotonic() - started
        last = result.stderr.strip().splitlines()[-1] if result.stderr.strip() else ""
        if result.returncode == 2:
            raise BadInput(last)
        if result.returncode != 0:
            raise RuntimeError(f"vkpath exited with {result.returncode}: {last}")
        parts = {"exr": open(out, "rb").read()}
        if aov:
            parts["variance"] = open(os.path.join(work, "part.variance.exr"), "rb").read()
        node = ray.get_runtime_context().get_node_id()[:8]
        return parts, seconds, node
    finally:
        shutil.rmtree(work, ignore_errors=True)


def parse(argv):
    if "--" in argv:
        split = argv.index("--")
        argv, flags = argv[:split], argv[split + 1:]
    else:
        flags = []
    p = argparse.ArgumentParser(prog="vkpath_ray.py", description=__doc__.split("\n")[0])
    p.add_argument("scene")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("-s", "--spp", type=int, required=True)
    group = p.add_mutually_exclusive_group()
    group.add_argument("--chunks", type=int, help="number of chunks (default 8)")
    group.add_argument("--chunk-spp", type=int, help="samples per chunk")
    p.add_argument("--address", help="a running Ray cluster (default: start one on this machine)")
    p.add_argument("--num-cpus", type=int, help="CPUs of the local cluster (without --address)")
    p.add_argument("--cpus-per-task", type=int, default=1)
    p.add_argument("--gpus-per-task", type=float, help="default: 1 where the cluster has GPUs, else 0")
    p.add_argument("--retries", type=int, default=3, help="resubmissions of a failed chunk (default 3)")
    p.add_argument("--aov", choices=["variance"])
    p.add_argument("--vkpath", default=shutil.which("vkpath") or os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "vkpath"))
    args = p.parse_args(argv)
    args.flags = flags

    def refuse(message):
        print(f"vkpath_ray: {message}", file=sys.stderr)
        sys.exit(2)

    if args.spp < 1:
        refuse("-s: samples per pixel must be at least 1")
    if args.chunks is not None and args.chunks < 1 or args.chunk_spp is not None and args.chunk_spp < 1:
        refuse("--chunks and --chunk-spp must be at least 1")
    if args.retries < 0:
        refuse("--retries must be at least 0")
    for flag in flags:
        if flag.split("=")[0] in FORBIDDEN:
            refuse(f"{flag}: the driver sets the outputs and sample ranges itself; give -o and -s before --")
    args.vkpath = os.path.abspath(args.vkpath)
    if not os.access(args.vkpath, os.X_OK):
        refuse(f"{args.vkpath}: no vkpath executable (--vkpath)")
    if not os.path.isfile(args.scene):
        refuse(f"{args.scene}: no such file")
    args.scene = os.path.abspath(args.scene)
    return args


def main(argv):
    args = parse(argv)
    # Ray 2.59 and later start clusters (`ray start --head`) with token
    # authentication, and a driver that joins one must present the token; one
    # without authentication accepts it as well (measured with Ray 2.60). Ray
    # reads the mode when it is imported.
    token = os.environ.get("RAY_AUTH_TOKEN") or os.environ.get("RAY_AUTH_TOKEN_PATH") or os.path.exists(
        os.path.expanduser("~/.ray/auth_token"))
    if args.address and token:
        os.environ.setdefault("RAY_AUTH_MODE", "token")
    try:
        import ray
    except ImportError:
        print("vkpath_ray: the Python package ray is missing: pip install ray", file=sys.stderr)
        return 1
    ranges = chunk_ranges(args.spp, args.chunks or (None if args.chunk_spp else 8), args.chunk_spp)
    # Ray's GPU numbers follow the PCI order that Vulkan lists GPUs in (vulkan_device_index).
    os.environ.setdefault("CUDA_DEVICE_ORDER", "PCI_BUS_ID")
    ray.init(address=args.address, num_cpus=None if args.address else args.num_cpus,
             include_dashboard=False, logging_level="ERROR", log_to_driver=False)
    try:
        gpus = args.gpus_per_task
        if gpus is None:
            gpus = 1 if ray.cluster_resources().get("GPU", 0) > 0 else 0
        task = ray.remote(render_chunk).options(num_gpus=gpus, num_cpus=0 if gpus else args.cpus_per_task,
                                                max_retries=0)
        threads = 0 if gpus else args.cpus_per_task
        print(f"vkpath_ray: {args.spp} spp in {len(ranges)} chunks on {ray.cluster_resources().get('CPU', 0):.0f} "
              f"CPUs, {ray.cluster_resources().get('GPU', 0):.0f} GPUs; each task asks for "
              f"{'%g GPU' % gpus if gpus else '%d CPU' % args.cpus_per_task}", file=sys.stderr)

        def submit(i):
            first, count = ranges[i]
            return task.remote(args.vkpath, args.scene, first, count, args.flags, args.aov is not None, threads)

        started = time.monotonic()
        pending = {submit(i): i for i in range(len(ranges))}
        attempts = [1] * len(ranges)
        parts = [None] * len(ranges)
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            i = pending.pop(ready[0])
            first, count = ranges[i]
            try:
                parts[i], seconds, node = ray.get(ready[0])
            except Exception as error:  # the task's exception, or Ray's for a lost worker or node
                cause = getattr(error, "cause", None)
                if isinstance(cause, BadInput) or isinstance(error, BadInput):
                    print(f"vkpath_ray: chunk {first}:{count}: {cause or error}", file=sys.stderr)
                    return 2
                reason = str(cause or error).strip().splitlines()[-1] if str(cause or error).strip() else type(error).__name__
                if attempts[i] > args.retries:
                    print(f"vkpath_ray: chunk {first}:{count} failed {attempts[i]} times, last: "
                          f"{type(error).__name__}: {reason}", file=sys.stderr)
                    return 1
                attempts[i] += 1
                print(f"vkpath_ray: chunk {first}:{count} failed ({type(error).__name__}: {reason}); "
                      f"retrying, attempt {attempts[i]} of {args.retries + 1}", file=sys.stderr)
                pending[submit(i)] = i
                continue
            done = sum(p is not None for p in parts)
            elapsed = time.monotonic() - started
            print(f"vkpath_ray: chunk {first}:{count} done on node {node} in {seconds:.2f} s; "
                  f"{done}/{len(ranges)} chunks, {elapsed:.1f} s, ETA {elapsed / done * (len(ranges) - done):.1f} s",
                  file=sys.stderr)
    finally:
        ray.shutdown()

    # Merge beside the output, so that only the merged EXR appears there.
    output = os.path.abspath(args.output)
    os.makedirs(os.path.dirname(output), exist_ok=True)
    folder = tempfile.mkdtemp(prefix=".vkpath-parts-", dir=os.path.dirname(output))
    try:
        paths = []
        for i, part in enumerate(parts):
            path = os.path.join(folder, f"part{i}.exr")
            open(path, "wb").write(part["exr"])
            if args.aov:
                open(os.path.join(folder, f"part{i}.variance.exr"), "wb").write(part["variance"])
            paths.append(path)
        command = [args.vkpath, "merge"] + paths + ["-o", output] + (["--aov", "variance"] if args.aov else [])
        merged = subprocess.run(command, capture_output=True, text=True)
        sys.stderr.write(merged.stderr)
        if merged.returncode != 0:
            return merged.returncode
        sys.stdout.write(merged.stdout)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    print(f"vkpath_ray: {args.spp} spp in {len(ranges)} chunks, {time.monotonic() - started:.2f} s from the first "
          f"submission to merged", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
