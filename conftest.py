"""Collection rules for the whole checkout (the doctests of ``uio_ring`` and the tests).

The compiled loops' doctests call numba, an optional dependency (extra ``fast``, included in
``test``): without it they are not collected, as the numba tests skip.
"""

import importlib.util

collect_ignore = [] if importlib.util.find_spec("numba") else ["uio_ring/numeric/linear_kernel.py"]
