import sys

from linkstress.cli import main

sys.exit(main())
