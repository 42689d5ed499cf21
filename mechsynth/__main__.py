import os
import sys

from .cli import EXIT_INTERRUPTED, main

if __name__ == "__main__":
    rc = main()
    if rc == EXIT_INTERRUPTED:  # a second Ctrl-C during shutdown must not turn it into a signal
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(rc)
    sys.exit(rc)
