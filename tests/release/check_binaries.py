"""Checks that shipped binaries run on the oldest Linux we promise: no glibc symbol newer than
GLIBC_2.31 (Debian 11, Ubuntu 20.04), and no shared library outside glibc, except those shipped
beside them (libgomp.so.1 beside the modules).

    python3 tests/release/check_binaries.py FILE...

Prints one line per binary, one line per problem, and exits 1 when there is a problem.
"""
import os
import re
import subprocess
import sys

NEWEST_GLIBC = (2, 31)
# glibc's own libraries: present on every Linux with glibc.
GLIBC_LIBRARIES = {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "librt.so.1",
                   "ld-linux-x86-64.so.2"}


def glibc_versions(path):
    """Versions of the GLIBC_x.y symbol versions the binary needs, as tuples."""
    text = subprocess.run(["objdump", "-T", path], capture_output=True, text=True, check=True).stdout
    return {tuple(int(n) for n in v.split(".")) for v in re.findall(r"\bGLIBC_(\d+(?:\.\d+)+)\b", text)}


def needed_libraries(path):
    text = subprocess.run(["readelf", "-d", path], capture_output=True, text=True, check=True).stdout
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", text)


def problems(path):
    found = []
    newer = sorted(v for v in glibc_versions(path) if v > NEWEST_GLIBC)
    if newer:
        found.append(f"needs GLIBC_{'.'.join(map(str, newer[-1]))}, newer than "
                     f"GLIBC_{'.'.join(map(str, NEWEST_GLIBC))}")
    beside = set(os.listdir(os.path.dirname(os.path.abspath(path))))
    for library in needed_libraries(path):
        if library not in GLIBC_LIBRARIES and library not in beside:
            found.append(f"needs {library}, which is neither part of glibc nor shipped beside it")
    return found


def main(paths):
    failed = False
    for path in paths:
        found = problems(path)
        newest = max(glibc_versions(path), default=None)
        print(f"{path}: newest glibc symbol GLIBC_{'.'.join(map(str, newest)) if newest else '-'}, "
              f"needs {', '.join(needed_libraries(path)) or 'nothing'}")
        for problem in found:
            print(f"  {path}: {problem}")
        failed |= bool(found)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
