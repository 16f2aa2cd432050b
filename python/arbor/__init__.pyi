"""Type stubs of the package arbor (PEP 561): the names it exports. The extension's own names
are typed in _arbor.pyi."""
from typing import Final

import numpy as np

from ._arbor import Scene as Scene
from ._arbor import __version__ as __version__
from ._arbor import kernel_set as kernel_set
from ._arbor import read_rays as read_rays

hit_dtype: Final[np.dtype[np.void]]
hit_normal_dtype: Final[np.dtype[np.void]]
point_dtype: Final[np.dtype[np.void]]
hit_inst_dtype: Final[np.dtype[np.void]]
hit_inst_normal_dtype: Final[np.dtype[np.void]]
point_inst_dtype: Final[np.dtype[np.void]]
MISS: Final[int]

__all__ = ["Scene", "read_rays", "kernel_set", "hit_dtype", "hit_normal_dtype", "point_dtype", "hit_inst_dtype",
           "hit_inst_normal_dtype", "point_inst_dtype", "MISS", "__version__"]
