import os
import signal
import sys

from .cli import EXIT_INTERRUPTED, EXIT_TERMINATED, main

if __name__ == "__main__":
    rc = main()
    # the work is done: a Ctrl-C during the interpreter's shutdown must not turn the exit
    # status into a signal (or print a traceback)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    if rc in (EXIT_INTERRUPTED, EXIT_TERMINATED):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(rc)
    sys.exit(rc)
