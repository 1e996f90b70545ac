"""The add-on's modules form layers: none imports a module that imports it back, directly or
through others (late imports inside functions count), so each can be read and tested on its own."""
import ast
import os

ADDON = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "addon")


def module_files():
    files = {}
    for folder, _, names in os.walk(os.path.join(ADDON, "many_worlds")):
        for name in names:
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                module = os.path.relpath(path, ADDON)[:-3].replace(os.sep, ".")
                files[module.removesuffix(".__init__")] = path
    return files


def imports_of(module, path, modules):
    package = module if path.endswith("__init__.py") else module.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(open(path).read())):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[:len(package.split(".")) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module
            for alias in node.names:
                name = f"{target}.{alias.name}"
                if name in modules:
                    found.add(name)
                elif target in modules and alias.name != "_native":
                    found.add(target)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name in modules)
    found.discard(module)
    return found


def test_no_module_imports_one_that_imports_it_back():
    modules = module_files()
    graph = {m: imports_of(m, p, modules) for m, p in modules.items()}

    def reaches(start, goal):
        seen, todo = set(), [start]
        while todo:
            here = todo.pop()
            if here == goal:
                return True
            if here not in seen:
                seen.add(here)
                todo.extend(graph[here])
        return False

    cycles = sorted((m, n) for m in graph for n in graph[m] if reaches(n, m))
    assert not cycles, f"import cycles through: {cycles}"
    # The check sees the imports it is about (not a vacuous pass).
    assert "many_worlds.core.engine" in graph["many_worlds.operators.run_poller"] | set().union(
        *(graph[m] for m in graph["many_worlds.operators.run_poller"]))
