"""`python -m culinarycut ...`: see culinarycut.cli."""
import sys

try:
    from culinarycut.cli import main
except ImportError as err:  # most likely the generated stubs are missing: say so without a traceback
    print(f"error: {err}", file=sys.stderr)
    sys.exit(2)

sys.exit(main())
