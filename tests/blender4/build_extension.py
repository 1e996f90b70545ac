"""Builds the Blender 4.2+ extension zip of the add-on for linux-x64 or windows-x64, and the
add-on zip for 3.x (Linux only).

    python3 tests/blender4/build_extension.py [--addon addon/many_worlds] [--out build/extension]
        [--platform linux-x64|windows-x64] [--binaries build-release/dist] [--legacy]

Blender's extension docs prescribe Python wheels for compiled Python modules: Blender installs the
wheels that match its own Python and platform into its extensions' site-packages when the
extension is enabled. So each built module (`_native.cpython-3XY-x86_64-linux-gnu.so` on Linux,
`_native.cp3XY-win_amd64.pyd` on Windows; 3.11 for the official 4.2-5.0 builds, 3.13 for 5.1+
and Debian's 4.3, 3.14 for Debian's 5.2) goes into its own wheel of a package
`many_worlds_native`, and the zip gets a two-line `_native.py` in place of the modules that
hands `from . import _native` the wheel's module. The engine executable (bin/mwb-engine, or
bin/mwb-engine.exe) is not a Python module and stays where the add-on looks for it.

With --binaries, the engine and modules come from a release build (native/release/build_release.sh:
bin/mwb-engine, modules/_native*.so and the libgomp.so.1 they load, which goes into each wheel
beside the module) instead of the checkout's own build. --platform windows-x64 takes them from the
Windows cross build's dist folder (native/release/windows/build_windows.sh: bin/mwb-engine.exe,
modules/_native.cp3XY-win_amd64.pyd, which load nothing of ours), build-windows/dist by default.

Writes OUT/many_worlds-VERSION-linux_x64.zip or -windows_x64.zip (Blender's name for a
per-platform build), whose manifest lists that platform only, and prints its path. --legacy writes
OUT/many_worlds-VERSION-linux_x64-addon.zip instead: the package folder with the modules beside
the code, for Preferences > Add-ons > Install in Blender 3.x and 4.0-4.1.
Plain Python 3.11+, no Blender needed; `blender -c extension validate` checks the extension.
"""
import argparse
import base64
import dataclasses
import hashlib
import io
import os
import re
import sys
import tomllib
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WHEEL_PACKAGE = "many_worlds_native"


@dataclasses.dataclass(frozen=True)
class Platform:
    """What differs between the platforms a zip is built for."""
    name: str                  # Blender's platform name, as the manifest lists it
    engine: str                # the engine's path in the add-on (core/paths.py looks there)
    module: str                # the compiled module's file name, 3XY for the Python version
    module_re: re.Pattern      # the same, matched: groups (major, minor)
    wheel_tag: str             # the wheel's platform tag
    companion_re: re.Pattern | None  # shared libraries the modules load from their own folder
    binaries: str | None       # the dist folder used without --binaries; None: the checkout's build
    legacy: bool               # whether --legacy makes an add-on zip for Blender 3.x-4.1

    @property
    def zip_suffix(self):
        return self.name.replace("-", "_")


PLATFORMS = {p.name: p for p in (
    Platform("linux-x64", "bin/mwb-engine", "_native.cpython-3XY-x86_64-linux-gnu.so",
             re.compile(r"^_native\.cpython-(\d)(\d+)-x86_64-linux-gnu\.so$"), "linux_x86_64",
             re.compile(r"^lib.*\.so"), None, True),
    Platform("windows-x64", "bin/mwb-engine.exe", "_native.cp3XY-win_amd64.pyd",
             re.compile(r"^_native\.cp(\d)(\d+)-win_amd64\.pyd$"), "win_amd64", None,
             os.path.join(ROOT, "build-windows", "dist"), False),
)}
# Compiled files of any platform that package_files leaves out of the add-on's folder: a zip takes
# its binaries from binaries() alone, so it never holds another platform's.
COMPILED_SUFFIXES = (".pyc", ".so", ".pyd", ".dll")
ENGINES = {p.engine for p in PLATFORMS.values()}
# The source manifest names every platform the add-on supports; each zip's copy names its own.
PLATFORMS_RE = re.compile(r"^platforms\s*=\s*\[[^\]]*\]", re.M)
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


def make_wheel(platform, module_path, version, python_tag, companions=()):
    """One wheel holding the module at many_worlds_native/_native..., and the shared libraries it
    loads from its own folder; returns (filename, bytes)."""
    dist_info = f"{WHEEL_PACKAGE}-{version}.dist-info"
    files = [
        (f"{WHEEL_PACKAGE}/__init__.py", b'"""The native module of the Many-Worlds Browser add-on."""\n'),
        (f"{WHEEL_PACKAGE}/{os.path.basename(module_path)}", read(module_path)),
    ] + [(f"{WHEEL_PACKAGE}/{os.path.basename(p)}", read(p)) for p in companions] + [
        (f"{dist_info}/METADATA",
         f"Metadata-Version: 2.1\nName: {WHEEL_PACKAGE}\nVersion: {version}\n"
         "Summary: Native module of the Many-Worlds Browser Blender extension\n".encode()),
        (f"{dist_info}/WHEEL",
         f"Wheel-Version: 1.0\nGenerator: many_worlds build_extension.py\nRoot-Is-Purelib: false\n"
         f"Tag: {python_tag}-{python_tag}-{platform.wheel_tag}\n".encode()),
    ]
    record = [record_line(name, data) for name, data in files] + [f"{dist_info}/RECORD,,"]
    files.append((f"{dist_info}/RECORD", ("\n".join(record) + "\n").encode()))
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as wheel:
        for name, data in files:
            zip_entry(wheel, name, data)
    return f"{WHEEL_PACKAGE}-{version}-{python_tag}-{python_tag}-{platform.wheel_tag}.whl", buffer.getvalue()


def manifest_for_zip(text, platform, wheel_paths):
    """The manifest with this platform alone and a `wheels` list; top-level keys must come before
    the first [table]."""
    if re.search(r"^wheels\s*=", text, re.M):
        raise SystemExit("build_extension: the source manifest already lists wheels; this script writes them")
    text = PLATFORMS_RE.sub(f'platforms = ["{platform.name}"]', text, count=1)
    lines = text.splitlines(keepends=True)
    at = next((i for i, line in enumerate(lines) if line.lstrip().startswith("[")), len(lines))
    entry = "wheels = [\n" + "".join(f'  "./{p}",\n' for p in wheel_paths) + "]\n\n"
    return "".join(lines[:at] + [entry] + lines[at:])


def package_files(addon_dir):
    """(relative path, absolute path) of everything that ships, except compiled code of any platform."""
    for folder, dirs, files in os.walk(addon_dir):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            rel = os.path.relpath(os.path.join(folder, name), addon_dir).replace(os.sep, "/")
            if name.endswith(COMPILED_SUFFIXES) or ".so." in name or rel in ENGINES:
                continue
            yield rel, os.path.join(folder, name)


def binaries(platform, addon_dir, release_dir):
    """(modules, companions, engine): the compiled modules, the shared libraries they load from
    their own folder, and the engine; from a release build or else from the checkout's build."""
    module_dir = os.path.join(release_dir, "modules") if release_dir else addon_dir
    engine = os.path.join(release_dir or addon_dir, platform.engine)
    names = sorted(os.listdir(module_dir)) if os.path.isdir(module_dir) else []
    modules = [os.path.join(module_dir, n) for n in names if platform.module_re.match(n)]
    companions = [os.path.join(module_dir, n) for n in names
                  if platform.companion_re and platform.companion_re.match(n)]
    if not modules:
        raise SystemExit(f"build_extension: no {platform.module} in {module_dir}: build first")
    if not os.access(engine, os.X_OK):
        raise SystemExit(f"build_extension: {engine} is missing: build first")
    return modules, companions, engine


def read_manifest(addon_dir, platform):
    with open(os.path.join(addon_dir, "blender_manifest.toml"), "rb") as f:
        text = f.read().decode()
    manifest = tomllib.loads(text)
    if not PLATFORMS_RE.search(text) or platform.name not in manifest["platforms"]:
        raise SystemExit(f"build_extension: the manifest's platforms do not include {platform.name}")
    return text, manifest


def write_zip(zip_path, entries):
    """entries: (name, bytes, executable); written to a side file first, so a zip is never partial."""
    with zipfile.ZipFile(zip_path + ".part", "w") as archive:
        for name, data, executable in entries:
            zip_entry(archive, name, data, executable)
    os.replace(zip_path + ".part", zip_path)


def build(platform, addon_dir, out_dir, release_dir=None):
    manifest_text, manifest = read_manifest(addon_dir, platform)
    modules, companions, engine = binaries(platform, addon_dir, release_dir)
    wheels = []
    for path in modules:
        major, minor = platform.module_re.match(os.path.basename(path)).groups()
        wheels.append(make_wheel(platform, path, manifest["version"], f"cp{major}{minor}", companions))
    wheel_paths = [f"wheels/{filename}" for filename, _ in wheels]

    entries = []
    for rel, path in package_files(addon_dir):
        if rel == "blender_manifest.toml":
            entries.append((rel, manifest_for_zip(manifest_text, platform, wheel_paths).encode(), False))
        else:
            entries.append((rel, read(path), os.access(path, os.X_OK) and not rel.endswith(".py")))
    entries.append((platform.engine, read(engine), True))
    entries.append(("_native.py", SHIM.format(package=WHEEL_PACKAGE).encode(), False))
    entries += [(rel, data, False) for (_, data), rel in zip(wheels, wheel_paths)]
    os.makedirs(out_dir, exist_ok=True)
    zip_path = os.path.join(out_dir, f"{manifest['id']}-{manifest['version']}-{platform.zip_suffix}.zip")
    write_zip(zip_path, entries)
    return zip_path, wheel_paths


def build_legacy(platform, addon_dir, out_dir, release_dir=None):
    """The add-on zip of Blender 3.x and 4.0-4.1: one top folder, the modules beside the code (each
    Python imports the one tagged for it) and no extension manifest."""
    _, manifest = read_manifest(addon_dir, platform)
    modules, companions, engine = binaries(platform, addon_dir, release_dir)
    top = manifest["id"]
    entries = [(f"{top}/{rel}", read(path), os.access(path, os.X_OK) and not rel.endswith(".py"))
               for rel, path in package_files(addon_dir) if rel != "blender_manifest.toml"]
    entries.append((f"{top}/{platform.engine}", read(engine), True))
    entries += [(f"{top}/{os.path.basename(p)}", read(p), False) for p in modules + companions]
    os.makedirs(out_dir, exist_ok=True)
    zip_path = os.path.join(out_dir, f"{top}-{manifest['version']}-{platform.zip_suffix}-addon.zip")
    write_zip(zip_path, entries)
    return zip_path


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--addon", default=os.path.join(ROOT, "addon", "many_worlds"))
    parser.add_argument("--out", default=os.path.join(ROOT, "build", "extension"))
    parser.add_argument("--platform", choices=sorted(PLATFORMS), default="linux-x64")
    parser.add_argument("--binaries", help="a release build's dist folder (bin/, modules/); "
                        "for windows-x64 build-windows/dist by default")
    parser.add_argument("--legacy", action="store_true",
                        help="the add-on zip for Blender 3.x and 4.0-4.1 (linux-x64 only)")
    args = parser.parse_args(argv)
    platform = PLATFORMS[args.platform]
    addon, out = os.path.abspath(args.addon), os.path.abspath(args.out)
    release = args.binaries or platform.binaries
    release = os.path.abspath(release) if release else None
    if args.legacy and not platform.legacy:
        parser.error(f"--legacy: the add-on zip for Blender 3.x and 4.0-4.1 is made for Linux only; "
                     f"for {platform.name} leave it out and build the 4.2+ extension")
    if args.legacy:
        print(build_legacy(platform, addon, out, release))
        return 0
    zip_path, wheel_paths = build(platform, addon, out, release)
    for path in wheel_paths:
        print(f"build_extension: {path}", file=sys.stderr)
    print(zip_path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
