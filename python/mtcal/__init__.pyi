"""mtcal: geometric accuracy of CNC machine tools, from Python (docs/python.md)."""
from ._mtcal import *  # noqa: F401,F403
from ._mtcal import Error as Error, InputError as InputError, ModelError as ModelError, __version__ as __version__

__all__: list[str]
