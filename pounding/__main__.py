import sys

from pounding.cli import main

sys.exit(main())
