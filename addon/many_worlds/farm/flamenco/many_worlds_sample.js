// SPDX-License-Identifier: GPL-3.0-or-later
// Flamenco custom job type: sample a range of Many-Worlds Browser worlds in chunks, one Blender
// task per chunk, then merge the shards into one library with a task that waits for all of them.
// Install: copy this file into the Manager's `scripts/` folder (next to flamenco-manager) and
// restart the Manager; the job type then appears as "Many-Worlds Sample".

// The submitting Blender computes the shards (the chunks of worlds and their files) with the
// add-on's own plan, many_worlds.farm.plan, wherever the add-on is installed (a legacy add-on or an
// extension): this script only reads them.
const SHARDS_EVAL =
  "__import__('importlib').import_module(next(name for name in __import__('sys').modules " +
  "if name.rpartition('.')[2] == 'many_worlds') + '.farm.plan')" +
  ".flamenco_shards(settings.first_world, settings.world_count, settings.chunk_size)";

const JOB_TYPE = {
  label: "Many-Worlds Sample",
  settings: [
    { key: "world_count", type: "int32", default: 1000, required: true,
      description: "How many worlds to sample" },
    { key: "first_world", type: "int32", default: 0, description: "Index of the first world" },
    { key: "chunk_size", type: "int32", default: 100, visible: "submission",
      description: "Worlds per Blender task" },
    { key: "shards", type: "string", required: true, visible: "hidden", eval: SHARDS_EVAL,
      description: "The chunks of worlds and their shard files, as JSON [{worlds: 'A:B', file}]" },
    { key: "output_dir", type: "string", subtype: "dir_path", required: true, visible: "submission",
      description: "Shared folder for the shards and the merged library" },
    { key: "cli_script", type: "string", required: true, visible: "submission",
      description: "Path of many_worlds/cli.py as the Workers see it" },
    { key: "blendfile", type: "string", required: true, visible: "web",
      description: "Path of the .blend file to sample" },
  ],
};

// The output folder, as the Workers see it, says which separator they use.
function joinPath(dir, name) {
  const separator = dir.includes("\\") && !dir.includes("/") ? "\\" : "/";
  return dir.endsWith(separator) ? dir + name : dir + separator + name;
}

function cliArgs(settings) {
  return ["--python-exit-code", "1", "--python", settings.cli_script, "--"];
}

function shardsOf(settings) {
  const shards = JSON.parse(settings.shards || "[]");
  if (!Array.isArray(shards) || shards.length === 0) {
    throw "shards is empty: submit the job from Blender with the Many-Worlds Browser add-on enabled";
  }
  return shards;
}

function compileJob(job) {
  const settings = job.settings;
  const shardFiles = [];
  const sampleTasks = [];
  for (const shard of shardsOf(settings)) {
    const file = joinPath(settings.output_dir, shard.file);
    const task = author.Task("sample " + shard.worlds, "blender");
    task.addCommand(author.Command("blender-render", {
      exe: "{blender}",
      exeArgs: "{blenderArgs}",
      argsBefore: [],
      blendfile: settings.blendfile,
      args: cliArgs(settings).concat(["sample", "--worlds", shard.worlds, "--out", file]),
    }));
    job.addTask(task);
    sampleTasks.push(task);
    shardFiles.push(file);
  }
  const merged = joinPath(settings.output_dir, "merged.mwb");
  const mergeTask = author.Task("merge", "blender");
  mergeTask.addCommand(author.Command("exec", {
    exe: "{blender}",
    args: ["-b", "--factory-startup"].concat(cliArgs(settings), ["merge", "--overwrite", merged], shardFiles),
  }));
  for (const task of sampleTasks) {
    mergeTask.addDependency(task);
  }
  job.addTask(mergeTask);
}
