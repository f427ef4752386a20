"""mtcal: geometric accuracy of CNC machine tools, from Python (docs/python.md)."""
from ._mtcal import *  # noqa: F401,F403
from ._mtcal import __version__  # noqa: F401
