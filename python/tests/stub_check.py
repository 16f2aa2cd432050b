"""Compares type stubs (.pyi) with the module they describe: the public names, whether each is a
function, class, property or value, and every function's parameters (names, order, positional or
keyword-only, defaults). The stub is read with ast; the module's signatures come from inspect or,
for pybind11's functions (which inspect cannot read), from the first line of their __doc__, which
pybind11 writes as `name(param: type = default, *, ...) -> type`."""
import ast
import inspect
import math

# A parameter: (name, kind, default) with kind "positional" (positional or keyword) or "keyword"
# (keyword-only), and default the repr of its value (None: no default).
Param = tuple


def _default(node):
    """The repr of a default written as an expression (`inf` and `nan` as math's), else its text."""
    if node is None:
        return None
    text = ast.unparse(node)
    try:
        return repr(eval(text, {"__builtins__": {}, "inf": math.inf, "nan": math.nan, "True": True, "False": False, "None": None}))
    except Exception:
        return text


def _params(args: ast.arguments):
    pos = args.posonlyargs + args.args
    defaults = [None] * (len(pos) - len(args.defaults)) + list(args.defaults)
    out = [(a.arg, "positional", _default(d)) for a, d in zip(pos, defaults)]
    out += [(a.arg, "keyword", _default(d)) for a, d in zip(args.kwonlyargs, args.kw_defaults)]
    if args.vararg:
        out.append(("*" + args.vararg.arg, "varargs", None))
    if args.kwarg:
        out.append(("**" + args.kwarg.arg, "varargs", None))
    return out


def _decorators(fn):
    return {ast.unparse(d) for d in fn.decorator_list}


def _public(name):
    return not name.startswith("_") or name in ("__init__", "__version__", "__call__")


def stub_api(source):
    """{name: (kind, detail)} of a stub's public names: ("function", params), ("class", {member:
    (kind, detail)}), ("property", None), ("value", None); an import `from .m import x as x` is
    ("import", "m.x")."""
    api = {}
    for node in ast.parse(source).body:
        if isinstance(node, ast.FunctionDef) and _public(node.name):
            api[node.name] = ("function", _params(node.args))
        elif isinstance(node, ast.ClassDef) and _public(node.name):
            members = {}
            for m in node.body:
                if isinstance(m, ast.FunctionDef) and _public(m.name):
                    deco = _decorators(m)
                    members[m.name] = ("property", None) if "property" in deco else ("function", _params(m.args))
            api[node.name] = ("class", members)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and _public(node.target.id):
            api[node.target.id] = ("value", None)
        elif isinstance(node, ast.ImportFrom):
            for alias in node.names:
                if alias.asname == alias.name and _public(alias.name):  # an explicit re-export
                    api[alias.name] = ("import", f"{node.module}.{alias.name}")
    return api


def signature_of(obj):
    """The parameters of a Python or pybind11 function."""
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        first = (obj.__doc__ or "").strip().splitlines()[0] if obj.__doc__ else ""
        tree = ast.parse(f"def {first.split('(', 1)[0]}({first.split('(', 1)[1].rsplit(')', 1)[0]}): ...")
        return _params(tree.body[0].args)
    kinds = {inspect.Parameter.KEYWORD_ONLY: "keyword", inspect.Parameter.VAR_POSITIONAL: "varargs",
             inspect.Parameter.VAR_KEYWORD: "varargs"}
    out = []
    for p in sig.parameters.values():
        name = {inspect.Parameter.VAR_POSITIONAL: "*", inspect.Parameter.VAR_KEYWORD: "**"}.get(p.kind, "") + p.name
        default = None if p.default is inspect.Parameter.empty or p.kind in kinds and kinds[p.kind] == "varargs" else repr(p.default)
        out.append((name, kinds.get(p.kind, "positional"), default))
    return out


def module_api(module, names):
    """{name: (kind, detail)} of the given names of a module, as stub_api describes a stub."""
    api = {}
    for name in names:
        obj = getattr(module, name)
        if inspect.isclass(obj):
            members = {}
            for m, raw in vars(obj).items():
                if not _public(m) or m == "__init__" and raw is object.__init__:
                    continue
                if isinstance(raw, property):
                    members[m] = ("property", None)
                elif isinstance(raw, (staticmethod, classmethod)) or callable(raw):
                    members[m] = ("function", signature_of(getattr(obj, m)))
            api[name] = ("class", members)
        elif callable(obj):
            api[name] = ("function", signature_of(obj))
        else:
            api[name] = ("value", None)
    return api


def _compare(stub, mod, where, problems):
    for name in sorted(set(stub) | set(mod)):
        at = f"{where}{name}"
        if name not in mod:
            problems.append(f"{at}: in the stub, not in the module")
            continue
        if name not in stub:
            problems.append(f"{at}: in the module, not in the stub")
            continue
        (sk, sd), (mk, md) = stub[name], mod[name]
        if sk != mk:
            problems.append(f"{at}: a {sk} in the stub, a {mk} in the module")
        elif sk == "class":
            _compare(sd, md, at + ".", problems)
        elif sk == "function" and sd != md:
            problems.append(f"{at}: parameters differ: stub {sd}, module {md}")


def differences(stub_source, module, names=None):
    """What a stub and its module disagree on, one line each (empty: they agree). `names` are the
    module names to compare (default: the module's public names, or its __all__)."""
    stub = stub_api(stub_source)
    if names is None:
        names = getattr(module, "__all__", None) or [n for n in vars(module) if _public(n)]
    imports = {n: d for n, (k, d) in stub.items() if k == "import"}
    stub = {n: v for n, v in stub.items() if v[0] != "import"}
    mod = module_api(module, [n for n in names if n not in imports])
    problems = []
    _compare(stub, mod, "", problems)
    for name in imports:
        if name not in names:
            problems.append(f"{name}: re-exported by the stub, not by the module")
    return problems, imports
