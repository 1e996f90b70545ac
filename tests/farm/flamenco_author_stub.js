// A minimal stand-in for Flamenco Manager's job-compiler environment: loads a job type script,
// runs its compileJob() with the given settings, and prints the tasks as JSON; or, given
// --job-type, prints its JOB_TYPE (the settings the submitting Blender fills in).
// node flamenco_author_stub.js JOB_TYPE.js SETTINGS_JSON | --job-type
"use strict";
const fs = require("fs");
const vm = require("vm");

function makeAuthor() {
  return {
    Task(name, type) {
      return {
        name, type, commands: [], dependencies: [],
        addCommand(command) { this.commands.push(command); },
        addDependency(task) { this.dependencies.push(task.name); },
      };
    },
    Command(type, parameters) {
      return { type, parameters };
    },
  };
}

const [script, settingsJson] = process.argv.slice(2);
const context = vm.createContext({ author: makeAuthor(), console });
vm.runInContext(fs.readFileSync(script, "utf8"), context, { filename: script });
if (settingsJson === "--job-type") {
  process.stdout.write(JSON.stringify(vm.runInContext("JOB_TYPE", context)));
  process.exit(0);
}
const job = { settings: JSON.parse(settingsJson), tasks: [], addTask(task) { this.tasks.push(task); } };
// Flamenco fills in defaults for settings the submitter left out.
for (const setting of vm.runInContext("JOB_TYPE", context).settings) {
  if (!(setting.key in job.settings) && "default" in setting) job.settings[setting.key] = setting.default;
}
vm.runInContext("compileJob", context)(job);
const names = new Set();
for (const task of job.tasks) {
  if (names.has(task.name)) throw new Error("duplicate task name " + task.name);
  names.add(task.name);
}
process.stdout.write(JSON.stringify(job.tasks.map(({ name, type, commands, dependencies }) =>
  ({ name, type, commands, dependencies }))));
