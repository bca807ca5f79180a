"""Runs one of the `blender -b` test scripts (tests/blender/test_*.py) in a `bpy` module, as that
script's __main__, and exits with its status (os._exit: docs/VERSIONS.md, the 4.2.23 module's crash at
exit). Used to see which of the 3.4 tests run in the newer Blenders (docs/VERSIONS.md):

    PYTHONPATH=tests BLENDER_USER_SCRIPTS=build/scripts \\
        build/bpy-<version>/bin/python tests/bpy/run_in_bpy.py tests/blender/test_plane.py
"""
import os
import runpy
import sys
import traceback

status = 1
try:
    sys.argv = sys.argv[1:]
    runpy.run_path(sys.argv[0], run_name="__main__")
    status = 0
except SystemExit as leaving:
    status = leaving.code if isinstance(leaving.code, int) else (0 if leaving.code is None else 1)
except BaseException:  # noqa: B902 (whatever it was, the script failed)
    traceback.print_exc()
finally:
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
