"""`python -m culinarycut ...`: see culinarycut.cli."""
import sys

from culinarycut.cli import main

sys.exit(main())
