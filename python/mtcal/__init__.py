"""mtcal: geometric accuracy of CNC machine tools, from Python.

The functions of mtcal's C++ library with NumPy arrays in and out (docs/python.md):

    import numpy as np, mtcal
    m = mtcal.Machine.load("examples/machines/vmc-3axis.yaml")
    q = m.grid("X=0:500:11,Y=0:400:9,Z=-300:0:7")   # (N, 3) joint values, mm and rad
    e = mtcal.evaluate(m, q)                          # (N, 6): dx dy dz (mm), rx ry rz (rad)
    va = mtcal.volumetric(m, q).va                    # mm

Units inside are mm and rad; joint arrays have one column per axis in the machine's chain
order (Machine.axis_letters). Results carry to_dict(), which returns what the command's --json
prints. Errors raise mtcal.InputError (file, line, field) or mtcal.ModelError with the library's
messages; a bad array raises ValueError naming the argument.
"""

from . import _mtcal
from ._mtcal import *  # noqa: F401,F403
from ._mtcal import Error, InputError, ModelError, __version__  # noqa: F401

__all__ = [name for name in dir(_mtcal) if not name.startswith("_")]

# The classes and functions belong to the package as users import them (repr, help, pickling errors).
for _name in __all__:
    _obj = getattr(_mtcal, _name)
    try:
        _obj.__module__ = __name__
    except (AttributeError, TypeError):
        pass
del _name, _obj
