"""Builds the Blender 4.2+ extension zip of the add-on for linux-x64, and the add-on zip for 3.x.

    python3 tests/blender4/build_extension.py [--addon addon/many_worlds] [--out build/extension]
        [--binaries build-release/dist] [--legacy]

Blender's extension docs prescribe Python wheels for compiled Python modules: Blender installs the
wheels that match its own Python and platform into its extensions' site-packages when the
extension is enabled. So each built `_native.cpython-3XY-x86_64-linux-gnu.so` (3.11 for the
official 4.2-5.0 builds, 3.13 for 5.1+ and Debian's 4.3, 3.14 for Debian's 5.2) goes into its own wheel of a package
`many_worlds_native`, and the zip gets a two-line `_native.py` in place of the .so files that
hands `from . import _native` the wheel's module. The engine executable (bin/mwb-engine) is not a
Python module and stays where the add-on looks for it.

With --binaries, the engine and modules come from a release build (native/release/build_release.sh:
bin/mwb-engine, modules/_native*.so and the libgomp.so.1 they load, which goes into each wheel
beside the module) instead of the checkout's own build.

Writes OUT/many_worlds-VERSION-linux_x64.zip (Blender's name for a per-platform build) and prints
its path. --legacy writes OUT/many_worlds-VERSION-linux_x64-addon.zip instead: the package folder
with the modules beside the code, for Preferences > Add-ons > Install in Blender 3.x and 4.0-4.1.
Plain Python 3.11+, no Blender needed; `blender -c extension validate` checks the extension.
"""
import argparse
import base64
import hashlib
import io
import os
import re
import sys
import tomllib
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLATFORM = "linux-x64"
ENGINE = "bin/mwb-engine"
WHEEL_PACKAGE = "many_worlds_native"
NATIVE_RE = re.compile(r"^_native\.cpython-(\d)(\d+)-x86_64-linux-gnu\.so$")
# Fixed timestamps make the zip and wheels depend on their contents only.
EPOCH = (1980, 1, 1, 0, 0, 0)

SHIM = '''"""The compiled module comes from this extension's wheel (see wheels/), which Blender unpacks
into its extensions' site-packages when the extension is enabled."""
import importlib
import sys

sys.modules[__name__] = importlib.import_module("{package}._native")
'''


def zip_entry(archive, name, data, executable=False):
    info = zipfile.ZipInfo(name, EPOCH)
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = (0o100755 if executable else 0o100644) << 16
    archive.writestr(info, data)


def record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def read(path):
    with open(path, "rb") as f:
        return f.read()


def make_wheel(so_path, version, python_tag, companions=()):
    """One wheel holding the module at many_worlds_native/_native...so, and the shared libraries it
    loads from its own folder; returns (filename, bytes)."""
    dist_info = f"{WHEEL_PACKAGE}-{version}.dist-info"
    files = [
        (f"{WHEEL_PACKAGE}/__init__.py", b'"""The native module of the Many-Worlds Browser add-on."""\n'),
        (f"{WHEEL_PACKAGE}/{os.path.basename(so_path)}", read(so_path)),
    ] + [(f"{WHEEL_PACKAGE}/{os.path.basename(p)}", read(p)) for p in companions] + [
        (f"{dist_info}/METADATA",
         f"Metadata-Version: 2.1\nName: {WHEEL_PACKAGE}\nVersion: {version}\n"
         "Summary: Native module of the Many-Worlds Browser Blender extension\n".encode()),
        (f"{dist_info}/WHEEL",
         f"Wheel-Version: 1.0\nGenerator: many_worlds build_extension.py\nRoot-Is-Purelib: false\n"
         f"Tag: {python_tag}-{python_tag}-linux_x86_64\n".encode()),
    ]
    record = [record_line(name, data) for name, data in files] + [f"{dist_info}/RECORD,,"]
    files.append((f"{dist_info}/RECORD", ("\n".join(record) + "\n").encode()))
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as wheel:
        for name, data in files:
            zip_entry(wheel, name, data)
    return f"{WHEEL_PACKAGE}-{version}-{python_tag}-{python_tag}-linux_x86_64.whl", buffer.getvalue()


def manifest_with_wheels(text, wheel_paths):
    """The manifest with a `wheels` list; top-level keys must come before the first [table]."""
    if re.search(r"^wheels\s*=", text, re.M):
        raise SystemExit("build_extension: the source manifest already lists wheels; this script writes them")
    lines = text.splitlines(keepends=True)
    at = next((i for i, line in enumerate(lines) if line.lstrip().startswith("[")), len(lines))
    entry = "wheels = [\n" + "".join(f'  "./{p}",\n' for p in wheel_paths) + "]\n\n"
    return "".join(lines[:at] + [entry] + lines[at:])


def package_files(addon_dir):
    """(relative path, absolute path) of everything that ships, except compiled code."""
    for folder, dirs, files in os.walk(addon_dir):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            rel = os.path.relpath(os.path.join(folder, name), addon_dir).replace(os.sep, "/")
            if name.endswith((".pyc", ".so")) or ".so." in name or rel == ENGINE:
                continue
            yield rel, os.path.join(folder, name)


def binaries(addon_dir, release_dir):
    """(modules, companions, engine): the compiled modules, the shared libraries they load from
    their own folder, and the engine; from a release build or else from the checkout's build."""
    module_dir = os.path.join(release_dir, "modules") if release_dir else addon_dir
    engine = os.path.join(release_dir, "bin", "mwb-engine") if release_dir else os.path.join(addon_dir, ENGINE)
    names = sorted(os.listdir(module_dir)) if os.path.isdir(module_dir) else []
    modules = [os.path.join(module_dir, n) for n in names if NATIVE_RE.match(n)]
    companions = [os.path.join(module_dir, n) for n in names if n.startswith("lib") and ".so" in n]
    if not modules:
        raise SystemExit(f"build_extension: no _native.cpython-3XY-x86_64-linux-gnu.so in {module_dir}: build first")
    if not os.access(engine, os.X_OK):
        raise SystemExit(f"build_extension: {engine} is missing: build first")
    return modules, companions, engine


def read_manifest(addon_dir):
    with open(os.path.join(addon_dir, "blender_manifest.toml"), "rb") as f:
        text = f.read().decode()
    manifest = tomllib.loads(text)
    if PLATFORM not in manifest.get("platforms", [PLATFORM]):
        raise SystemExit(f"build_extension: the manifest's platforms do not include {PLATFORM}")
    return text, manifest


def write_zip(zip_path, entries):
    """entries: (name, bytes, executable); written to a side file first, so a zip is never partial."""
    with zipfile.ZipFile(zip_path + ".part", "w") as archive:
        for name, data, executable in entries:
            zip_entry(archive, name, data, executable)
    os.replace(zip_path + ".part", zip_path)


def build(addon_dir, out_dir, release_dir=None):
    manifest_text, manifest = read_manifest(addon_dir)
    modules, companions, engine = binaries(addon_dir, release_dir)
    wheels = []
    for path in modules:
        major, minor = NATIVE_RE.match(os.path.basename(path)).groups()
        wheels.append(make_wheel(path, manifest["version"], f"cp{major}{minor}", companions))
    wheel_paths = [f"wheels/{filename}" for filename, _ in wheels]

    entries = []
    for rel, path in package_files(addon_dir):
        if rel == "blender_manifest.toml":
            entries.append((rel, manifest_with_wheels(manifest_text, wheel_paths).encode(), False))
        else:
            entries.append((rel, read(path), os.access(path, os.X_OK) and not rel.endswith(".py")))
    entries.append((ENGINE, read(engine), True))
    entries.append(("_native.py", SHIM.format(package=WHEEL_PACKAGE).encode(), False))
    entries += [(rel, data, False) for (_, data), rel in zip(wheels, wheel_paths)]
    os.makedirs(out_dir, exist_ok=True)
    zip_path = os.path.join(out_dir, f"{manifest['id']}-{manifest['version']}-{PLATFORM.replace('-', '_')}.zip")
    write_zip(zip_path, entries)
    return zip_path, wheel_paths


def build_legacy(addon_dir, out_dir, release_dir=None):
    """The add-on zip of Blender 3.x and 4.0-4.1: one top folder, the modules beside the code (each
    Python imports the one tagged for it) and no extension manifest."""
    _, manifest = read_manifest(addon_dir)
    modules, companions, engine = binaries(addon_dir, release_dir)
    top = manifest["id"]
    entries = [(f"{top}/{rel}", read(path), os.access(path, os.X_OK) and not rel.endswith(".py"))
               for rel, path in package_files(addon_dir) if rel != "blender_manifest.toml"]
    entries.append((f"{top}/{ENGINE}", read(engine), True))
    entries += [(f"{top}/{os.path.basename(p)}", read(p), False) for p in modules + companions]
    os.makedirs(out_dir, exist_ok=True)
    zip_path = os.path.join(out_dir, f"{top}-{manifest['version']}-{PLATFORM.replace('-', '_')}-addon.zip")
    write_zip(zip_path, entries)
    return zip_path


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--addon", default=os.path.join(ROOT, "addon", "many_worlds"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "extension"))
    parser.add_argument("--binaries", help="a release build's dist folder (bin/, modules/)")
    parser.add_argument("--legacy", action="store_true", help="the add-on zip for Blender 3.x and 4.0-4.1")
    args = parser.parse_args(argv)
    addon, out = os.path.abspath(args.addon), os.path.abspath(args.out)
    release = os.path.abspath(args.binaries) if args.binaries else None
    if args.legacy:
        print(build_legacy(addon, out, release))
        return 0
    zip_path, wheel_paths = build(addon, out, release)
    for path in wheel_paths:
        print(f"build_extension: {path}", file=sys.stderr)
    print(zip_path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
