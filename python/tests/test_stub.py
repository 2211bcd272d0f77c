"""The type stub and docstrings follow the library's tables: every public name of the module is in
the stub and back, every query key and method appears in the stub's signatures and help()."""
import ast
import importlib.util
import os

import glintscope

STUB = os.path.join(os.path.dirname(glintscope.__file__), "glintscope.pyi")


def stub_tree():
    with open(STUB, encoding="utf-8") as f:
        return ast.parse(f.read())


def test_the_stub_is_current():
    spec = importlib.util.spec_from_file_location("make_stub", os.path.join(os.path.dirname(__file__), "..", "make_stub.py"))
    make_stub = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make_stub)
    with open(STUB, encoding="utf-8") as f:
        assert f.read() == make_stub.stub()


def test_the_stub_names_every_public_name_and_no_other():
    tree = stub_tree()
    names = {node.name for node in tree.body if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
    names |= {node.target.id for node in tree.body if isinstance(node, ast.AnnAssign)}
    public = {name for name in dir(glintscope) if not name.startswith("_")} | {"__version__"}
    assert names == public
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name != "Error":  # Error adds nothing to ValueError
            members = {m.name for m in node.body if isinstance(m, ast.FunctionDef)}
            members |= {m.target.id for m in node.body if isinstance(m, ast.AnnAssign)}
            actual = {m for m in dir(getattr(glintscope, node.name)) if not m.startswith("_")}
            assert members - {"__init__", "__iter__", "__array__", "__enter__", "__exit__"} == actual, node.name


def test_every_query_key_and_method_is_in_the_signatures_and_help():
    functions = {node.name: node for node in stub_tree().body if isinstance(node, ast.FunctionDef)}
    keywords = {a.arg for a in functions["lobe"].args.kwonlyargs}
    for key in glintscope.query_keys():
        if key["name"] in ("heightfield", "quantity"):
            continue
        name = "lambda_" if key["name"] == "lambda" else key["name"]
        assert name in keywords
        assert key["help"] in glintscope.lobe.__doc__ and key["help"] in ast.get_docstring(functions["lobe"])
    for method in glintscope.methods():
        for function in (["lobe", "bsdf"] if "brdf" in method["quantities"] else []) + (["ndf"] if "ndf" in method["quantities"] else []):
            assert method["reference"] in getattr(glintscope, function).__doc__
            for option in method["options"]:
                assert option["help"] in ast.get_docstring(functions[function])
