"""The package's layering: each subpackage imports only what lies before it in the pipeline."""

import ast

import pytest

from conftest import ROOT

PACKAGE = ROOT / "beeoptics"
#: Modules every stage may use.
SHARED = {"spectra", "headframe", "raycasting", "jit", "replicates", "_exports"}
#: What each part of the package may import: eye → light → vision → images, io below all,
#: pipeline, the command-line tool and the Python API above all. Vision sees neither scenes nor eyes.
ALLOWED = {
    "_exports": set(),
    "headframe": set(),
    "raycasting": set(),
    "jit": set(),
    "replicates": set(),
    "io": {"io", "headframe", "_exports"},
    "spectra": {"io"},
    "eye": {"eye", "io", *SHARED},
    "world": {"world", "io", *SHARED},
    "sky": {"sky", "io", *SHARED},
    "light": {"light", "sky", "eye", "io", *SHARED},
    "vision": {"vision", "io", *SHARED},
    "images": {"images", "vision", "light", "sky", "eye", "io", *SHARED},
    # The navigation stage reads its maps and eyes through the API's records and calls beeoptics.navigation.
    "pipeline": {"pipeline", "api", "navigation", "images", "vision", "light", "sky", "eye", "world", "io",
                 *SHARED},
    "cli": {"pipeline", "api", "images", "vision", "light", "sky", "eye", "world", "io", *SHARED},
    # The tracer's entry points, which only the API calls (test_stages_reach_the_tracer_through_the_api).
    "tracing": {"vision", "light", "sky", "eye", "io", *SHARED},
    # Views for navigation: maps traced by the receptors' tracer, resampled to eyes.
    "navigation": {"navigation", "tracing", "vision", "light", "sky", "eye", "io", *SHARED},
    # The Python API, the stages' one way to the tracer: it builds an eye and a meadow as their stages do.
    "api": {"tracing", "navigation", "pipeline", "images", "vision", "light", "sky", "eye", "world", "io", *SHARED},
    # The closed loop: an agent's moves and what the API's looks show it, casting its steps into the scene.
    "loop": {"api", "io", *SHARED},
}


def part(module):
    """The part of the package a dotted module name (below ``beeoptics``) belongs to."""
    return module.split(".")[0]


def imports(path):
    """The parts of the package a source file imports, with the line of each import."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("beeoptics"):
            # From the package itself, only its modules count (not, say, __version__).
            names = [node.module] if node.module != "beeoptics" else [
                f"beeoptics.{a.name}" for a in node.names
                if (PACKAGE / a.name).is_dir() or (PACKAGE / f"{a.name}.py").is_file()]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names if a.name.startswith("beeoptics")]
        else:
            continue
        for name in names:
            below = name.removeprefix("beeoptics").lstrip(".")
            if below:
                found.append((part(below), node.lineno))
    return found


def sources():
    return sorted(p for p in PACKAGE.rglob("*.py"))


def test_every_module_belongs_to_a_known_part():
    for path in sources():
        rel = path.relative_to(PACKAGE).with_suffix("")
        if rel.parts != ("__init__",):
            assert part(".".join(rel.parts)) in ALLOWED, rel


@pytest.mark.parametrize("path", sources(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_point_down_the_pipeline(path):
    rel = path.relative_to(PACKAGE).with_suffix("")
    if rel.parts == ("__init__",):
        return
    mine = part(".".join(rel.parts))
    for other, line in imports(path):
        assert other in ALLOWED[mine], f"{path.relative_to(ROOT)}:{line}: {mine} imports {other}"


def module_imports(path):
    """The package's modules a source file imports, by dotted name below ``beeoptics``: at its top and
    inside functions alike (an import deferred for speed still ties the two modules)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("beeoptics"):
            base = node.module.removeprefix("beeoptics").lstrip(".")
            for a in node.names:
                # ``from beeoptics.eye import fieldmodel`` imports the module eye.fieldmodel.
                sub = PACKAGE.joinpath(*base.split("."), a.name) if base else PACKAGE / a.name
                found.add(f"{base}.{a.name}".lstrip(".") if sub.is_dir() or sub.with_suffix(".py").is_file()
                          else base)
        elif isinstance(node, ast.Import):
            found |= {a.name.removeprefix("beeoptics.") for a in node.names if a.name.startswith("beeoptics.")}
    return found - {""}


def test_no_two_modules_import_each_other_even_by_a_detour():
    # A circle of imports (eye.build → eye.description → eye.given → eye.build) leaves no module to read first.
    graph = {}
    for path in sources():
        rel = path.relative_to(PACKAGE).with_suffix("")
        if rel.name != "__init__":
            graph[".".join(rel.parts)] = {m for m in module_imports(path) if m != ".".join(rel.parts)}
    state = {}

    def visit(module, trail):
        state[module] = "open"
        for other in sorted(graph.get(module, ())):
            assert state.get(other) != "open", " → ".join([*trail[trail.index(other):], other])
            if other not in state:
                visit(other, [*trail, other])
        state[module] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])


#: The tracer's internals: what loads a scene into the tracer, builds its Embree scene, places receptors in it,
#: draws their rays, traces paths and turns their radiance into catches. The API (beeoptics.api) is the one
#: way to them, so that a stage, the command line and a benchmark trace alike and pass no dozen positional
#: arguments of their own; a module whose every name is internal is named with "*".
INTERNALS = {
    "beeoptics.tracing": {"*"},
    "beeoptics.light.integrator": {"*"},
    "beeoptics.light.batching": {"TraceSettings", "trace_bundles"},
    "beeoptics.light.sensors": {"cone_samples", "cone_sigma", "pinhole_rays"},
    "beeoptics.light.scene": {"load_scene", "raycasting_scene", "receptors_in_world", "posed", "relit",
                              "bee_camera"},
    "beeoptics.light.precision": {"adaptive_samples", "replicate_samples"},
    "beeoptics.vision.catches": {"quantum_catches"},
}
#: The stages: the workflow's stage functions and scripts, the command line and the benchmarks.
STAGES = sorted([*(PACKAGE / "pipeline").glob("*.py"), PACKAGE / "cli.py",
                 *(ROOT / "workflow" / "scripts").glob("*.py"), *(ROOT / "benchmarks").glob("*.py")])


def internal_uses(path):
    """The tracer's internals a source file imports: (line, name) pairs."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module in INTERNALS:
            names = INTERNALS[node.module]
            found += [(node.lineno, a.name) for a in node.names if "*" in names or a.name in names]
        elif isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names if a.name in INTERNALS]
    return found


@pytest.mark.parametrize("path", STAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_stages_reach_the_tracer_through_the_api(path):
    name = str(path.relative_to(ROOT))
    uses = internal_uses(path)
    past = [f"{name}:{line}: {what}" for line, what in uses]
    assert not past, f"past the API: {', '.join(past)}"


def test_the_stages_that_draw_nothing_import_no_matplotlib():
    """Remeshing, relaxing, tracing a flight's frames and the detection survey draw nothing: matplotlib, half a
    second of a job, is imported by the stage functions that draw; and they read no glTF (pygltflib, 30–40 ms,
    is imported where an OCES file is read or written)."""
    import subprocess
    import sys

    code = ("import sys, beeoptics.pipeline.eyes, beeoptics.pipeline.flights, beeoptics.pipeline.detection; "
            "print(' '.join(m for m in ('matplotlib', 'colour', 'plotly', 'pygltflib') if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == ""


def test_every_data_file_of_the_package_is_installed_with_it():
    """pyproject's package-data globs, as setuptools takes them (relative to each package's folder, ``*``
    within one folder), cover every file of the package that is not Python: a wheel or a non-editable
    install carries its data (the receptor sets in vision/data/receptor_sets were left out)."""
    import tomllib

    globs = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]
    installed = {f for package, patterns in globs.items() for pattern in patterns
                 for f in (ROOT / package.replace(".", "/")).glob(pattern) if f.is_file()}
    data = {f for f in PACKAGE.rglob("*") if f.is_file() and f.suffix not in (".py", ".pyc")
            and "__pycache__" not in f.parts}
    assert sorted(str(f.relative_to(ROOT)) for f in data - installed) == []
