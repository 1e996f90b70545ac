"""Splitting a world range into farm tasks and the command lines those tasks run: the one home of
the chunks and the shard names, which the Slurm scripts and the Flamenco job take from here."""
import json
import os

CLI_SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "cli.py")


def chunks(first_world, world_count, chunk_size):
    """[(a, b), ...] covering worlds first_world .. first_world + world_count - 1, b exclusive."""
    if world_count < 1 or chunk_size < 1 or first_world < 0:
        raise ValueError("world count and chunk size must be at least 1, the first world at least 0")
    end = first_world + world_count
    return [(a, min(a + chunk_size, end)) for a in range(first_world, end, chunk_size)]


def shard_name(a, b):
    """A shard's file name: a re-run task rewrites the same file (and writes it identically)."""
    return f"shard_{a:08d}_{b:08d}.mwb"


def flamenco_shards(first_world, world_count, chunk_size):
    """The Flamenco job's `shards` setting: JSON text [{"worlds": "A:B", "file": shard name}], one
    per chunk (the job type, farm/flamenco/many_worlds_sample.js, reads it and computes nothing)."""
    return json.dumps([{"worlds": f"{a}:{b}", "file": shard_name(a, b)}
                       for a, b in chunks(first_world, world_count, chunk_size)], separators=(",", ":"))


def cli_prefix(blender="blender", blend_file=None, cli_script=CLI_SCRIPT):
    """The start of every task command: Blender headless running the add-on's command line."""
    command = [blender, "-b"]
    if blend_file:
        command.append(blend_file)
    else:
        command.append("--factory-startup")
    return command + ["--python-exit-code", "1", "--python", cli_script, "--"]


def sample_command(blend_file, a, b, out_dir, blender="blender", threads=None, cli_script=CLI_SCRIPT):
    command = cli_prefix(blender, blend_file, cli_script) + [
        "sample", "--worlds", f"{a}:{b}", "--out", os.path.join(out_dir, shard_name(a, b))]
    if threads:
        command += ["--threads", str(threads)]
    return command


def merge_command(out_file, shard_files, blender="blender", cli_script=CLI_SCRIPT):
    """Merging again replaces an earlier result, so a re-run merge task succeeds."""
    return cli_prefix(blender, None, cli_script) + ["merge", "--overwrite", out_file, *shard_files]
