"""Makes the experiment scripts run with Debian's numpy and matplotlib (python3-numpy,
python3-matplotlib) even when another python3 (pyenv, a venv) comes first on PATH: if the
imports fail, the script re-executes itself once with /usr/bin/python3. Without a script to re-run
(python3 -c, a notebook) it raises ImportError instead."""

import os
import sys

DEBIAN_PYTHON = "/usr/bin/python3"


def ensure_numpy_matplotlib():
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
        return
    except ImportError:
        pass
    same = os.path.realpath(sys.executable) == os.path.realpath(DEBIAN_PYTHON)
    if not os.path.isfile(sys.argv[0] if sys.argv else ""):
        # python3 -c, an interactive session, a notebook: no script to re-run
        raise ImportError("numpy and matplotlib are needed for the figures (Debian 12: apt-get "
                          "install python3-numpy python3-matplotlib; or use " + DEBIAN_PYTHON + ")")
    if not same and os.access(DEBIAN_PYTHON, os.X_OK) and not os.environ.get("SCW_PY_REEXEC"):
        os.environ["SCW_PY_REEXEC"] = "1"
        os.execv(DEBIAN_PYTHON, [DEBIAN_PYTHON] + sys.argv)
    sys.exit("error: numpy and matplotlib are needed (Debian 12: apt-get install python3-numpy "
             "python3-matplotlib)")


ensure_numpy_matplotlib()
