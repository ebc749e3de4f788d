"""openseespy for the reference scripts of tests/opensees/, or exit 2 naming the install
command: a test that needs OpenSees fails loudly instead of skipping."""
import sys

try:
    from ops_import import ops
except Exception as exc:
    print(f"cannot import openseespy (pip install openseespy==3.7.1.2): {exc}", file=sys.stderr)
    sys.exit(2)

__all__ = ["ops"]
