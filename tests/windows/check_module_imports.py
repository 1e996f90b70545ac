"""Checks a Windows build of the module (_native.cp3XX-win_amd64.pyd) from its import and export
tables, as `objdump -p` prints them, the way Python on Windows will load it:
  - it exports PyInit__native, the function `import _native` calls;
  - every DLL it imports is Windows' own or python3XX.dll of its own Python version (no MinGW
    runtime DLL, which a Windows machine does not have);
  - every name it takes from python3XX.dll is one that version's headers declare (python3XX.def,
    made from them), so Python's DLL exports it.
    python3 check_module_imports.py MODULE.pyd PYTHON_DEF [OBJDUMP]
Prints one line per module; exits 1 naming every problem.
"""
import re
import subprocess
import sys

# DLLs every 64-bit Windows has in System32.
WINDOWS_DLLS = {"kernel32.dll", "msvcrt.dll", "user32.dll", "advapi32.dll", "ws2_32.dll", "bcrypt.dll"}


def tables(objdump_text):
    """({dll: [imported names]}, [exported names]) from `objdump -p`."""
    imports, exports = {}, []
    current, in_exports = None, False
    for line in objdump_text.splitlines():
        dll = re.match(r"\s*DLL Name: (\S+)", line)
        if dll:
            current = imports.setdefault(dll.group(1), [])
            continue
        if current is not None:
            entry = re.match(r"\s+[0-9a-f]+\s+\d+\s+(\S+)\s*$", line)
            if entry:
                current.append(entry.group(1))
                continue
            if not line.strip():
                current = None
        if line.startswith("[Ordinal/Name Pointer] Table"):
            in_exports = True
            continue
        if in_exports:
            name = re.match(r"\s+\[\s*\d+\]\s+(\S+)", line)
            if name:
                exports.append(name.group(1))
            elif not line.strip():
                in_exports = False
    return imports, exports


def declared(def_path):
    names = set()
    with open(def_path) as f:
        for line in f:
            parts = line.split()
            if parts and parts[0] not in ("LIBRARY", "EXPORTS"):
                names.add(parts[0])
    return names


def problems(module, def_path, objdump):
    tag = re.search(r"\.cp(\d+)-win_amd64\.pyd$", module)
    if not tag:
        return [f"{module}: not named _native.cp3XX-win_amd64.pyd"]
    python_dll = f"python{tag.group(1)}.dll"
    text = subprocess.run([objdump, "-p", module], capture_output=True, text=True, check=True).stdout
    imports, exports = tables(text)
    found = []
    if "PyInit__native" not in exports:
        found.append(f"does not export PyInit__native (exports: {', '.join(exports) or 'nothing'})")
    for dll in imports:
        if dll.lower() not in WINDOWS_DLLS and dll.lower() != python_dll:
            found.append(f"imports {dll}, which is neither Windows' own nor {python_dll}")
    if python_dll not in {d.lower() for d in imports}:
        found.append(f"does not import {python_dll}")
    known = declared(def_path)
    for dll, names in imports.items():
        if dll.lower() == python_dll:
            unknown = sorted(set(names) - known)
            if unknown:
                found.append(f"takes from {python_dll} names its headers do not declare: {', '.join(unknown)}")
    return found, imports


def main(module, def_path, objdump="x86_64-w64-mingw32-objdump"):
    found, imports = problems(module, def_path, objdump)
    if found:
        for problem in found:
            print(f"FAIL: {module}: {problem}")
        return 1
    python_names = sum(len(n) for d, n in imports.items() if d.lower().startswith("python"))
    print(f"{module.rsplit('/', 1)[-1]}: exports PyInit__native; imports {', '.join(sorted(imports))}; "
          f"all {python_names} names from Python's DLL are declared in its headers")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
