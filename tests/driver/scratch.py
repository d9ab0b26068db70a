"""A scratch directory for a test script's runs, removed when the script ends well.

scratch_dir(prefix) makes a new directory under the system's temporary directory. When the
script exits with status 0 every directory it made is removed; when it fails (a non-zero
sys.exit, an uncaught exception) they are kept and named on stderr, so that the outputs of
the failing run can be read. FDEM_KEEP_TEST_OUTPUT=1 keeps them in any case.
"""
import atexit
import os
import shutil
import sys
import tempfile

_made = []
_failed = False
_sys_exit = sys.exit


def _exit(status=None):
    global _failed
    _failed = _failed or not (status is None or status == 0)
    _sys_exit(status)


def _excepthook(kind, value, traceback):
    global _failed
    _failed = True
    sys.__excepthook__(kind, value, traceback)


def _clean_up():
    keep = _failed or os.environ.get("FDEM_KEEP_TEST_OUTPUT", "") not in ("", "0")
    for path in _made:
        if keep:
            print(f"the outputs are kept in {path}", file=sys.stderr)
        else:
            shutil.rmtree(path, ignore_errors=True)


def scratch_dir(prefix):
    if not _made:
        sys.exit = _exit
        sys.excepthook = _excepthook
        atexit.register(_clean_up)
    path = tempfile.mkdtemp(prefix=prefix)
    _made.append(path)
    return path
