"""The harness of the Python tests of examples/gdn: plain asserts, a test list, skips with a
message when the shared data set or an exported model is absent, exit status != 0 on failure.
Importing it puts examples/gdn on the path."""
from __future__ import annotations

import os
import sys
import traceback

GDN = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), 'examples', 'gdn')
sys.path.insert(0, GDN)

from dataset import default_data_dir  # noqa: E402

TESTS = []
SKIPPED = []


def test(fn):
    TESTS.append(fn)
    return fn


def data_dir():
    d = os.environ.get('LIESERVO_DATA') or default_data_dir()
    return d if os.path.isfile(os.path.join(d, 'val', 'targets.csv')) else None


def skip(name, why):
    SKIPPED.append(name)
    print(f'SKIP {name}: {why}')


def run():
    """Runs every registered test; the exit status: 1 if any failed."""
    passed = failed = 0
    for fn in TESTS:
        try:
            n_skip = len(SKIPPED)
            fn()
            if len(SKIPPED) == n_skip:
                print(f'ok   {fn.__name__}')
                passed += 1
        except Exception:
            failed += 1
            print(f'FAIL {fn.__name__}')
            traceback.print_exc()
    print(f'{passed} passed, {failed} failed' + (f', {len(SKIPPED)} skipped' if SKIPPED else ''))
    return 1 if failed else 0
