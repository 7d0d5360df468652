"""Regenerate the committed default models: ``python -m mjrft.models.generate``.

``--check`` only verifies that the committed files match the generators
(exit status 1 and a list of stale files otherwise).
"""

from __future__ import annotations

import argparse
import os
import sys

from . import MODEL_NAMES, model_path
from .biped import biped_xml
from .hexapod import hexapod_xml
from .humanoid import humanoid_xml
from .rigs import leg_rig_xml, plate_rig_xml
from .shoal import hexapod_shoal_xml

#: name -> (generator, kwargs)
DEFAULTS = {
    "hexapod": (hexapod_xml, dict(variant="rhex", sand=True)),
    "hexapod_rigid": (hexapod_xml, dict(variant="rhex", sand=False)),
    "hexapod_small": (hexapod_xml, dict(variant="small", sand=True)),
    "hexapod_small_rigid": (hexapod_xml, dict(variant="small", sand=False)),
    "biped": (biped_xml, dict(foot="cone", sand=True)),
    "biped_wedge": (biped_xml, dict(foot="wedge", sand=True)),
    "biped_rigid": (biped_xml, dict(foot="cone", sand=False)),
    "humanoid": (humanoid_xml, dict(sand=True)),
    "humanoid_cutout": (humanoid_xml, dict(foot_cutout=True, sand=True)),
    "humanoid_rigid": (humanoid_xml, dict(sand=False)),
    "plate_rig": (plate_rig_xml, dict()),
    "leg_rig": (leg_rig_xml, dict(shape="c")),
    "hexapod_shoal": (hexapod_shoal_xml, dict()),
}
assert tuple(DEFAULTS) == MODEL_NAMES


def generated(name: str) -> str:
    """The XML text the committed file ``name`` should contain."""
    func, kwargs = DEFAULTS[name]
    return func(**kwargs)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only check that the files are up to date")
    args = parser.parse_args(argv)
    stale = []
    for name in MODEL_NAMES:
        text = generated(name)
        path = model_path(name)
        old = open(path).read() if os.path.exists(path) else None
        if old == text:
            continue
        stale.append(path)
        if not args.check:
            with open(path, "w") as f:
                f.write(text)
            print(f"wrote {path}")
    if args.check and stale:
        print("stale models (run python -m mjrft.models.generate):\n  " + "\n  ".join(stale))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
