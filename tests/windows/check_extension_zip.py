"""Checks the windows-x64 extension zip against the cross build's dist folder it was made from:
  - its manifest lists the platform windows-x64 alone and a wheel per module;
  - bin/mwb-engine.exe is the dist's engine;
  - each wheel is tagged cp3XY-cp3XY-win_amd64 and holds many_worlds_native/_native.cp3XY-win_amd64.pyd,
    the dist's module;
  - nothing in the zip or its wheels is a Linux binary (an ELF file, a .so or bin/mwb-engine).
`blender -c extension validate` checks none of this: it takes a wheel of any platform.
    python3 check_extension_zip.py ZIP DIST
Prints one line; exits 1 naming every problem.
"""
import io
import os
import re
import sys
import tomllib
import zipfile

MODULE_RE = re.compile(r"^_native\.cp(\d+)-win_amd64\.pyd$")


def linux_binaries(archive, where):
    """The entries of an open zip that are Linux binaries, named with WHERE."""
    found = []
    for name in archive.namelist():
        base = os.path.basename(name)
        if (archive.read(name)[:4] == b"\x7fELF" or base.endswith(".so") or ".so." in base
                or name == "bin/mwb-engine"):
            found.append(f"{where}{name} is a Linux binary")
    return found


def check(zip_path, dist):
    problems = []
    archive = zipfile.ZipFile(zip_path)
    names = set(archive.namelist())
    manifest = tomllib.loads(archive.read("blender_manifest.toml").decode())
    if manifest.get("platforms") != ["windows-x64"]:
        problems.append(f"the manifest's platforms are {manifest.get('platforms')}, not [\"windows-x64\"]")

    engine = "bin/mwb-engine.exe"
    with open(os.path.join(dist, engine), "rb") as f:
        if engine not in names or archive.read(engine) != f.read():
            problems.append(f"{engine} is missing or is not {dist}/{engine}")

    tags = sorted(MODULE_RE.match(n).group(1) for n in os.listdir(os.path.join(dist, "modules"))
                  if MODULE_RE.match(n))
    expected_wheels = [f"./wheels/many_worlds_native-{manifest['version']}-cp{t}-cp{t}-win_amd64.whl"
                       for t in tags]
    if not tags or manifest.get("wheels") != expected_wheels:
        problems.append(f"the manifest's wheels are {manifest.get('wheels')}, not {expected_wheels}")
    problems += linux_binaries(archive, "")
    for tag, wheel_path in zip(tags, expected_wheels):
        name = wheel_path[2:]
        if name not in names:
            problems.append(f"{name} is missing")
            continue
        wheel = zipfile.ZipFile(io.BytesIO(archive.read(name)))
        module = f"_native.cp{tag}-win_amd64.pyd"
        with open(os.path.join(dist, "modules", module), "rb") as f:
            if f"many_worlds_native/{module}" not in wheel.namelist() or \
                    wheel.read(f"many_worlds_native/{module}") != f.read():
                problems.append(f"{name} does not hold many_worlds_native/{module} as in {dist}/modules")
        wheel_file = wheel.read(f"many_worlds_native-{manifest['version']}.dist-info/WHEEL").decode()
        if f"Tag: cp{tag}-cp{tag}-win_amd64\n" not in wheel_file:
            problems.append(f"{name} is not tagged cp{tag}-cp{tag}-win_amd64")
        problems += linux_binaries(wheel, f"{name}:")
    if problems:
        print(f"FAIL: {os.path.basename(zip_path)}:\n  " + "\n  ".join(problems))
        return 1
    print(f"{os.path.basename(zip_path)}: platforms = [\"windows-x64\"], {engine}, wheels for cp"
          + " and cp".join(tags) + " with their .pyd, the dist's bytes; no Linux binary")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(check(sys.argv[1], sys.argv[2]))
