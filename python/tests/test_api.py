"""The module's surface: the stub names every public name, each has a docstring, and help()
explains a call as the tool's --help explains its options."""
import ast
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
