"""lieservo: Lie groups, concentrated Gaussians, fusion and the discriminative Bayes filter of
pose-and-shear tactile servoing, in double precision (docs/python.md).

The package is the compiled module `lieservo._lieservo` (a pybind11 binding of the C++ headers,
examples/python/lieservo_module.cpp) under the name users import. This file's folder is not
named lieservo: on the path of the scripts beside it, that would shadow the built package.
"""
from . import _lieservo
from ._lieservo import *  # noqa: F401,F403  (the classes and functions; the binding has no __all__)
from ._lieservo import __version__  # noqa: F401

# The classes report `lieservo` as their module, as the documentation names them.
for _obj in vars(_lieservo).values():
    if isinstance(_obj, type) and _obj.__module__ == _lieservo.__name__:
        _obj.__module__ = __name__
del _obj
