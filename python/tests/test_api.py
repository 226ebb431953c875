"""The module's surface: the stub names every public name, each has a docstring, and help()
explains a call as the tool's --help explains its options."""
import ast
import inspect
import re
import pathlib

import dhdr

STUB = pathlib.Path(__file__).resolve().parent.parent / "dhdr" / "__init__.pyi"


def public_names():
    return {n for n in dir(dhdr) if not n.startswith("_")} - {"oiio"}


def stub_names():
    tree = ast.parse(STUB.read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
    return names - {"ArrayLike", "ImageLike", "Roi", "LightsLike", "__version__"}


def test_stub_matches_the_module():
    assert public_names() == stub_names()


def test_every_call_is_documented():
    for name in public_names():
        doc = getattr(dhdr, name).__doc__ or ""
        assert len(doc.strip()) > 40, name


def test_help_explains_options_like_the_tool():
    assert "reinhard-local" in dhdr.tone_map.__doc__ and "--op" in dhdr.tone_map.__doc__
    for option in ["ao", "background", "plate", "radiometric", "probes"]:
        assert option in dhdr.light.__doc__
    assert "dhdr-light" in dhdr.light.__doc__ and "dhdr-bloom" in dhdr.bloom.__doc__


def stub_signatures():
    """Each function's (and each class's methods') parameter names in the stub, one tuple an
    overload, without self."""
    found = {}

    def add(key, fn):
        a = fn.args
        names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs if x.arg != "self"]
        names += [x.arg for x in (a.vararg, a.kwarg) if x]
        found.setdefault(key, set()).add(tuple(names))

    for node in ast.parse(STUB.read_text()).body:
        if isinstance(node, ast.FunctionDef):
            add(node.name, node)
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                decorators = [getattr(d, "id", "") for d in item.decorator_list] \
                    if isinstance(item, ast.FunctionDef) else []
                if isinstance(item, ast.FunctionDef) and "property" not in decorators:
                    add(f"{node.name}.{item.name}", item)
    return found


def module_signatures(key):
    """The parameter names of each overload of a module function or method, from pybind11's
    signature lines (or Python's own signature for the functions written in Python)."""
    obj = dhdr
    for part in key.split("."):
        obj = getattr(obj, part)
    name = key.split(".")[-1]
    lines = re.findall(rf"^(?:\d+\. )?{re.escape(name)}\((.*)\) ->", obj.__doc__ or "", re.M)
    if not lines:
        return {tuple(p for p in inspect.signature(obj).parameters if p != "self")}
    out = set()
    for line in lines:
        # Split at the commas outside brackets and quotes: "size: Tuple[int, int] = (1, 2)".
        params, depth, quote, start = [], 0, "", 0
        for i, ch in enumerate(line + ","):
            if quote:
                quote = "" if ch == quote else quote
            elif ch in "'\"":
                quote = ch
            elif ch in "([{":
                depth += 1
            elif ch in ")]}":
                depth -= 1
            elif ch == "," and depth == 0:
                params.append(line[start:i].strip().split(":")[0].split("=")[0].strip())
                start = i + 1
        out.add(tuple(p for p in params if p not in ("self", "*", "*args", "**kwargs", "")))
    return out


def test_stub_signatures_match_the_module():
    wrong = {key: (names, module_signatures(key))
             for key, names in stub_signatures().items()
             if not key.split(".")[-1].startswith("__") and names != module_signatures(key)}
    assert not wrong, wrong
