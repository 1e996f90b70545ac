// SPDX-License-Identifier: GPL-3.0-or-later
// Flamenco custom job type: sample a range of Many-Worlds Browser worlds in chunks, one Blender
// task per chunk, then merge the shards into one library with a task that waits for all of them.
// Install: copy this file into the Manager's `scripts/` folder (next to flamenco-manager) and
// restart the Manager; the job type then appears as "Many-Worlds Sample".

const JOB_TYPE = {
  label: "Many-Worlds Sample",
  settings: [
    { key: "world_count", type: "int32", default: 1000, required: true,
      description: "How many worlds to sample" },
    { key: "first_world", type: "int32", default: 0, description: "Index of the first world" },
    { key: "chunk_size", type: "int32", default: 100, visible: "submission",
      description: "Worlds per Blender task" },
    { key: "output_dir", type: "string", subtype: "dir_path", required: true, visible: "submission",
      description: "Shared folder for the shards and the merged library" },
    { key: "cli_script", type: "string", required: true, visible: "submission",
      description: "Path of many_worlds/cli.py as the Workers see it" },
    { key: "blendfile", type: "string", required: true, visible: "web",
      description: "Path of the .blend file to sample" },
  ],
};

function joinPath(dir, name) {
  return dir.endsWith("/") ? dir + name : dir + "/" + name;
}

function pad8(n) {
  return String(n).padStart(8, "0");
}

function shardName(a, b) {
  return "shard_" + pad8(a) + "_" + pad8(b) + ".mwb";
}

function cliArgs(settings) {
  return ["--python-exit-code", "1", "--python", settings.cli_script, "--"];
}

function compileJob(job) {
  const settings = job.settings;
  if (settings.world_count < 1 || settings.chunk_size < 1 || settings.first_world < 0) {
    throw "world_count and chunk_size must be at least 1 and first_world at least 0";
  }
  const end = settings.first_world + settings.world_count;
  const shards = [];
  const sampleTasks = [];
  for (let a = settings.first_world; a < end; a += settings.chunk_size) {
    const b = Math.min(a + settings.chunk_size, end);
    const shard = joinPath(settings.output_dir, shardName(a, b));
    const task = author.Task("sample " + a + "-" + (b - 1), "blender");
    task.addCommand(author.Command("blender-render", {
      exe: "{blender}",
      exeArgs: "{blenderArgs}",
      argsBefore: [],
      blendfile: settings.blendfile,
      args: cliArgs(settings).concat(["sample", "--worlds", a + ":" + b, "--out", shard]),
    }));
    job.addTask(task);
    sampleTasks.push(task);
    shards.push(shard);
  }
  const merged = joinPath(settings.output_dir, "merged.mwb");
  const mergeTask = author.Task("merge", "blender");
  mergeTask.addCommand(author.Command("exec", {
    exe: "{blender}",
    args: ["-b", "--factory-startup"].concat(cliArgs(settings), ["merge", "--overwrite", merged], shards),
  }));
  for (const task of sampleTasks) {
    mergeTask.addDependency(task);
  }
  job.addTask(mergeTask);
}
