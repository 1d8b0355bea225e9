"""`dynpaint params`: every recipe parameter with its unit, range and default
(from params.py)."""
from .. import params


def _print_param(p):
    rng = f" range [{p.min}, {p.max}]" if p.min is not None else ""
    choices = f" one of: {', '.join(p.choices)}" if p.choices else ""
    unit = f" ({p.unit})" if p.unit else ""
    print(f"  {p.key} = {p.default!r}{unit}{rng}{choices}  {p.spec}\n      {p.help}")


def cmd_params(args):
    section = None
    for p in params.PARAMS:
        if p.section != section:
            section = p.section
            print(f"\n[{section}]")
        _print_param(p)
    print("\n[images]  (paths relative to the recipe; a frame-numbered name, walk_####.png or "
          "walk_%04d.png, is a sequence: §16)")
    for ch, (what, space) in params.CHANNELS.items():
        print(f"  {ch}: {what} [{space}]")
    print("\n[frames]  a painting that moves (§16): how its sequences and sprite sheets "
          "follow the scene's frames;\n          [frames.<channel>] sets one image's own "
          "mapping (any of these keys)")
    for p in params.FRAME_PARAMS:
        _print_param(p)
    print("\n[[lights]]  type = \"sun\" with direction = [x, y, z] (toward the light), or "
          "\"point\" with position = [x, y, z] (image widths from the painting's centre);\n"
          "            color = [r, g, b] (linear), strength = k ≥ 0 (pipeline.md §5)")


def add_parser(sub):
    """Register `params` on the command line's subparsers."""
    pa = sub.add_parser("params", help="list every recipe parameter with its unit, range, default",
                        description="List every key a recipe (painting.toml) may set, section "
                        "by section, with its default, unit, range, the § of docs/pipeline.md "
                        "it implements and what it does.")
    pa.set_defaults(func=cmd_params)
