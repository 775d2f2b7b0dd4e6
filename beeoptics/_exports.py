"""Each subpackage's public names, imported from their modules only when first used.

A subpackage lists its public functions and records by module, as
colour-science's ``__init__`` files do; importing them lazily (PEP 562)
keeps ``import beeoptics.io.errors`` or ``beeoptics --help`` from loading
Open3D, pymeshlab and the rest.
"""

from importlib import import_module


def exports(package, public):
    """``__all__`` and a module ``__getattr__`` for ``package``, from {module: names}."""
    where = {name: module for module, names in public.items() for name in names}

    def __getattr__(name):
        if name not in where:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(import_module(f"{package}.{where[name]}"), name)

    return sorted(where), __getattr__
