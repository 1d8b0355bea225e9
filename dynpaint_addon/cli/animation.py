"""`dynpaint animation FILE.blend --out VIDEO.mp4`: a .blend file's animation rendered as it
was saved — its scene, camera, frame range and render settings — in background Blender, each
frame baking its dynamic paintings' shadows as Blender does when it renders (issue 64: the
job a render farm runs for a .blend, one chunk of frames a task with `--only FIRST-LAST`)."""
from ..errors import CommandError
from .turntable import check_out, parse_only


def cmd_animation(args):
    frame_files = check_out(args)
    only = parse_only(args.only)
    from ..blender.headless import render_animation   # Blender only when asked for
    try:
        seconds, (first, last), paintings = render_animation(
            args.blend, args.out, only, frame_files, progress=lambda line: print(line, flush=True))
    except ValueError as exc:
        raise CommandError(str(exc)) from None
    count = last - first + 1
    lit = f"{paintings} dynamic painting{'s' if paintings != 1 else ''}" if paintings else \
        "no dynamic painting in its scene: rendered as Blender renders it"
    print(f"animation: frames {first}–{last} ({lit}) in {seconds:.1f} s "
          f"({seconds / count:.2f} s/frame) → {args.out}")


def add_parser(sub):
    """Register `animation` on the command line's subparsers."""
    an = sub.add_parser("animation", help="render a .blend file's animation (its paintings' "
                        "shadows baked each frame)",
                        description="Render a .blend file's animation as it was saved (its "
                        "scene, camera, frame range and render settings), each frame baking "
                        "its dynamic paintings' shadows, as Blender does with the add-on "
                        "enabled. A turntable made in Blender (Add Light Turntable) is its "
                        "animation.")
    an.add_argument("blend", metavar="FILE.blend", help="the .blend file (not changed)")
    an.add_argument("--out", required=True, help="video file (.mp4, H.264), or the frames' "
                    "files (frames/####.png: 16-bit PNG, #### the frame's number, each file "
                    "written whole)")
    an.add_argument("--only", metavar="FIRST-LAST",
                    help="render only these scene frames into --out's files: a render farm's "
                    "chunk")
    an.set_defaults(func=cmd_animation)
