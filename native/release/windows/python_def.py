"""Writes the module-definition file of a Windows CPython DLL from its headers: every name the
headers declare with PyAPI_FUNC (a function) or PyAPI_DATA (data), which is what an extension may
import from python3XX.dll. dlltool makes the import library from it.
    python3 python_def.py INCLUDE_DIR DLL_NAME OUT.def
"""
import os
import re
import sys

# The declared name follows the macro's (possibly nested) parentheses: PyAPI_FUNC(int) Name(...,
# PyAPI_DATA(PyTypeObject) Name; comments and line breaks may sit in between.
_TYPE = r"\((?:[^()]|\([^()]*\))*\)"
FUNC = re.compile(r"PyAPI_FUNC\s*" + _TYPE + r"\s*(\w+)\s*\(")
DATA = re.compile(r"PyAPI_DATA\s*" + _TYPE + r"\s*(\w+)\s*[;\[,]")
COMMENT = re.compile(r"/\*.*?\*/", re.S)


def declared_names(include_dir):
    functions, data = set(), set()
    for folder, _, files in os.walk(include_dir):
        for name in files:
            if not name.endswith(".h"):
                continue
            with open(os.path.join(folder, name), encoding="utf-8", errors="replace") as f:
                text = COMMENT.sub(" ", f.read())
            # The macros' own definitions (pyport.h) are not declarations.
            text = re.sub(r"#\s*define\s+PyAPI_(FUNC|DATA)\b.*", " ", text)
            functions.update(FUNC.findall(text))
            data.update(DATA.findall(text))
    # Only CPython's own names: the headers also declare stand-ins for other systems (the pthread
    # stubs for WASI), which python3XX.dll does not export and which must not shadow the real ones.
    own = re.compile(r"_?P[yY]")
    functions = {name for name in functions if own.match(name)}
    data = {name for name in data if own.match(name)}
    return functions, data - functions


def main(include_dir, dll, out):
    functions, data = declared_names(include_dir)
    if len(functions) < 500:
        sys.exit(f"python_def.py: only {len(functions)} functions declared in {include_dir}: not CPython's headers?")
    with open(out, "w") as f:
        f.write(f"LIBRARY {dll}\nEXPORTS\n")
        f.writelines(f"  {name}\n" for name in sorted(functions))
        f.writelines(f"  {name} DATA\n" for name in sorted(data))


if __name__ == "__main__":
    main(*sys.argv[1:4])
