"""The root of the mjrft repository, which is not a package.

Python imports this folder as ``mjrft`` only when a script runs from the folder that holds a
clone named ``mjrft``: the current folder comes first on ``sys.path``, so ``import mjrft`` would
find the repository instead of the installed package (``mjrft/`` inside it, installed by
``make setup`` / ``pip install -e .``), import an empty namespace, register no environments, and
``gymnasium.make("mjrft/...")`` would say the id does not exist. This file makes that an error
that says what happened.
"""

import os as _os

raise ImportError(
    f"'import mjrft' found the mjrft repository folder {_os.path.dirname(_os.path.abspath(__file__))!r} "
    "instead of the mjrft package, because the script runs from the folder that holds the repository. "
    "Run it from another folder (or from inside the repository), or rename the clone; the package itself "
    "is installed by 'make setup' (pip install -e .)."
)
