"""Runs pytest inside Blender and passes its exit code back.

blender -b --factory-startup --python-exit-code 1 --python tests/blender/run.py -- [pytest args]
The add-on folder of this checkout is put first on sys.path so `many_worlds` is this build's.
"""
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [os.path.dirname(os.path.abspath(__file__))]
# Blender keeps running after a script returns; exit with pytest's verdict.
sys.exit(int(pytest.main(["-q", "-p", "no:cacheprovider", *args])))
