"""`python -m culinarycut ...` and the `culinarycut` command: see culinarycut.cli."""
import sys


def main() -> int:
    try:
        from culinarycut.cli import main as cli_main
    except ImportError as err:  # most likely the generated stubs are missing: say so without a traceback
        print(f"error: {err}", file=sys.stderr)
        return 2
    return cli_main()


if __name__ == "__main__":
    sys.exit(main())
