"""Deprecation shims for the public API's renames (the glossary's "Renames waiting").

An old name is accepted for one release after its rename, with a :class:`DeprecationWarning`
that names the new one, then removed:

* :func:`renamed_parameters` for a parameter renamed in a function's signature;
* :func:`moved_names` for a module attribute (function or class) renamed in a package face.
"""
import functools
import warnings
from typing import Callable, Dict

# the release that removes the old names (the one after the release that renamed them)
REMOVED_IN = "0.4"


def _warn(old: str, new: str, where: str, stacklevel: int) -> None:
    warnings.warn(f"{where}: {old!r} is deprecated, use {new!r} (the old name goes in "
                  f"{REMOVED_IN}).", DeprecationWarning, stacklevel=stacklevel + 1)


def renamed_parameters(**old_to_new: str) -> Callable:
    """Decorate a function whose keyword parameters were renamed, ``old="new"``.

    A call with an old name warns and passes the value on under the new one; giving both names
    is a ``TypeError``. The wrapper keeps the function's signature (``inspect.signature``
    follows ``__wrapped__``), so the old names appear nowhere in the documented API.

    Parameters
    ----------
    **old_to_new : str
        Each old parameter name with its new name.

    Returns
    -------
    callable
        The decorator.
    """
    def deco(fn):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            for old, new in old_to_new.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{fn.__name__}() got both {old!r} and its new name "
                                        f"{new!r}: give {new!r} only.")
                    _warn(old, new, f"{fn.__name__}()", 2)
                    kwargs[new] = kwargs.pop(old)
            return fn(*args, **kwargs)
        wrapper.renamed_parameters = dict(old_to_new)
        return wrapper
    return deco


def moved_names(module: str, namespace: Dict[str, object], **old_to_new: str) -> Callable:
    """A module ``__getattr__`` (PEP 562) that serves each old attribute name as its new one.

    Parameters
    ----------
    module : str
        The module's name, for the warning (``__name__``).
    namespace : dict
        The module's globals, where the new names are.
    **old_to_new : str
        Each old attribute name with its new name.

    Returns
    -------
    callable
        The module's ``__getattr__``: it warns and returns the new object for an old name, and
        raises ``AttributeError`` for any other missing name.
    """
    def __getattr__(name: str):
        if name in old_to_new:
            new = old_to_new[name]
            _warn(name, new, module, 2)
            return namespace[new]
        raise AttributeError(f"module {module!r} has no attribute {name!r}")
    return __getattr__
