import sys

from uio_ring.cli import main

sys.exit(main())
