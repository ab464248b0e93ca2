"""``puppet mocap mapping CLIP``: the mapping puppet builds for a clip's rig, as YAML to
edit (``> my.yaml``; then ``--mapping my.yaml``). Only argparse at the top: the command
line starts fast."""

from __future__ import annotations

import argparse


def register(msub) -> None:
    """``mapping`` under ``puppet mocap`` (``msub``: its sub-parsers)."""
    parser = msub.add_parser(
        "mapping", help="the mapping puppet builds for a clip's humanoid rig, as YAML",
        description="Recognise a BVH clip's humanoid rig by its joint names (CMU, "
                    "Mixamo, Unity/VRM, CC_Base_*, Rokoko, SMPL...) and write the mapping "
                    "puppet builds for it - joints, unit, up axis, floor, the feet's rest "
                    "angle - as YAML on standard output: puppet mocap mapping CLIP > "
                    "my.yaml, edit it, then play --mocap CLIP --mapping my.yaml.")
    parser.add_argument("clip", help="a BVH file, or a name: assets/mocap/NAME.bvh")
    parser.add_argument("--character", default=None, metavar="NAME",
                        help="the figure it is for (its leg gives the size; default the "
                             "biped)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from puppet.data.catalog import find, load_character_named
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.mapping_text import mapping_yaml
    from puppet.mocap.rigs import recognise

    path = find("clip", args.clip)
    character = load_character_named(args.character)[0] if args.character else None
    rig = recognise(read_bvh(path), character)
    import textwrap

    said = textwrap.wrap(f"Built by 'puppet mocap mapping {args.clip}' from {Path(path).name}: "
                         f"{rig.summary()}.", 86)
    said += ["Edit it, check it (puppet check FILE), play it (--mapping FILE); see "
             "docs/interfaces.md, section 15.1."]
    print(mapping_yaml(rig.mapping, said), end="")
    return 0
