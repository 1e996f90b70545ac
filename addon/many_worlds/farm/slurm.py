"""Submit sampling to a Slurm cluster: a job array with one `sample` task per chunk of worlds,
and a `merge` job that runs after every array task succeeded (--dependency=afterok).

    python3 -m many_worlds.farm.slurm scene.blend --worlds 1000 --chunk 100 --out /shared/run1
    (PYTHONPATH pointing at the add-on folder; the cluster's nodes must see the same paths)
"""
import argparse
import os
import shlex
import subprocess
import sys

from . import plan


def job_scripts(blend_file, first_world, world_count, chunk_size, out_dir, blender="blender",
                cli_script=plan.CLI_SCRIPT, threads=None):
    """(array script, merge script, task count): sbatch scripts for the sampling and the merge."""
    ranges = plan.chunks(first_world, world_count, chunk_size)
    logs = os.path.join(out_dir, "logs")
    cases = "\n".join(
        f"  {k}) exec {shlex.join(plan.sample_command(blend_file, a, b, out_dir, blender, threads, cli_script))} ;;"
        for k, (a, b) in enumerate(ranges))
    array = f"""#!/bin/sh
#SBATCH --job-name=mwb-sample
#SBATCH --output={logs}/sample_%A_%a.log
# One chunk of worlds per array task; a task that fails can simply be re-run.
set -eu
case "$SLURM_ARRAY_TASK_ID" in
{cases}
  *) echo "no chunk for array task $SLURM_ARRAY_TASK_ID" >&2; exit 2 ;;
esac
"""
    shards = [os.path.join(out_dir, plan.shard_name(a, b)) for a, b in ranges]
    merged = os.path.join(out_dir, "merged.mwb")
    merge = f"""#!/bin/sh
#SBATCH --job-name=mwb-merge
#SBATCH --output={logs}/merge_%j.log
set -eu
exec {shlex.join(plan.merge_command(merged, shards, blender, cli_script))}
"""
    return array, merge, len(ranges)


def submit(blend_file, first_world, world_count, chunk_size, out_dir, blender="blender", threads=None,
           sbatch="sbatch", extra_args=()):
    """Writes the scripts into out_dir and submits them; returns (array job id, merge job id)."""
    os.makedirs(os.path.join(out_dir, "logs"), exist_ok=True)
    array, merge, tasks = job_scripts(os.path.abspath(blend_file), first_world, world_count, chunk_size,
                                      os.path.abspath(out_dir), blender, threads=threads)
    array_path = os.path.join(out_dir, "sample_array.sh")
    merge_path = os.path.join(out_dir, "merge.sh")
    for path, text in ((array_path, array), (merge_path, merge)):
        with open(path, "w") as f:
            f.write(text)
    array_id = _sbatch([sbatch, "--parsable", f"--array=0-{tasks - 1}", *extra_args, array_path])
    merge_id = _sbatch([sbatch, "--parsable", f"--dependency=afterok:{array_id}", *extra_args, merge_path])
    return array_id, merge_id


def _sbatch(command):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"{command[0]} failed: {result.stderr.strip() or result.stdout.strip()}")
    # --parsable prints "jobid" or "jobid;cluster".
    return result.stdout.strip().split(";")[0]


def main(argv=None):
    parser = argparse.ArgumentParser(prog="many_worlds.farm.slurm", description=__doc__.split("\n\n")[0])
    parser.add_argument("blend_file")
    parser.add_argument("--worlds", type=int, required=True, help="how many worlds")
    parser.add_argument("--first", type=int, default=0, help="index of the first world")
    parser.add_argument("--chunk", type=int, default=100, help="worlds per array task")
    parser.add_argument("--out", required=True, help="shared folder for shards, logs and merged.mwb")
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--threads", type=int, help="threads per task (default: all of the node's)")
    args, extra = parser.parse_known_args(argv)
    try:
        array_id, merge_id = submit(args.blend_file, args.first, args.worlds, args.chunk, args.out, args.blender,
                                    args.threads, extra_args=extra)
    except (ValueError, RuntimeError, OSError) as error:
        print(f"many_worlds.farm.slurm: {error}", file=sys.stderr)
        return 2
    print(f"submitted sampling array {array_id} and merge {merge_id}; result: {os.path.join(args.out, 'merged.mwb')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
