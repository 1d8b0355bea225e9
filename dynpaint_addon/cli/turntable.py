"""`dynpaint turntable RECIPE --out VIDEO.mp4`: the main job — a light orbits the
painting once, rendered by Cycles or EEVEE in background Blender, each frame's shadows baked."""
import os

from ..core.frames import is_pattern
from ..errors import CommandError
from ..inputs import memory
from ..inputs.layered_files import is_layered_file
from ..inputs.recipe import load_recipe
from ..inputs.samples import recipe_help
from .notes import on_words, print_notes


def video_size_fits(width, height):
    """Whether FFmpeg takes a frame of this size (its av_image_check_size: (w + 128)·(h + 128)
    under INT_MAX / 8); a larger --size ended in a traceback after the set-up (issue 60)."""
    return (width + 128) * (height + 128) < (2**31 - 1) // 8


def parse_only(only):
    """`--only A-B` (or `N`) → (A, B), a chunk's first and last frames; None → None.

    >>> parse_only("5-8"), parse_only("3"), parse_only(None)
    ((5, 8), (3, 3), None)
    """
    if only is None:
        return None
    try:
        a, _, b = only.partition("-")
        first, last = int(a), int(b or a)
    except ValueError:
        raise CommandError(f"--only {only}: frames as FIRST-LAST, e.g. 1-12") from None
    if first > last:
        raise CommandError(f"--only {only}: the first frame after the last")
    return first, last


def frames_range(only, frames):
    """`--only A-B` (or `N`) → (A, B), the orbit's frames a chunk renders (1 … frames).

    >>> frames_range("5-8", 24), frames_range("3", 24), frames_range(None, 24)
    ((5, 8), (3, 3), (1, 24))
    """
    first, last = parse_only(only) or (1, frames)
    if not 1 <= first <= last <= frames:
        raise CommandError(f"--only {only}: frames between 1 and {frames} (--frames), the "
                           f"first not after the last")
    return first, last


def check_out(args):
    """CommandError for an --out a turntable or animation cannot write (with --only) →
    whether it names frame files (frames/####.png) rather than a video."""
    out_ext = os.path.splitext(args.out)[1].lower()
    frame_files = is_pattern(os.path.basename(args.out))
    if frame_files and out_ext != ".png":
        raise CommandError(f"--out {args.out}: frames are written as PNG files "
                           f"(frames/####.png)")
    if not frame_files and out_ext not in (".mp4", ".mkv", ".mov"):
        article = "an" if args.command[0] in "aeiou" else "a"
        raise CommandError(f"--out {args.out}: {article} {args.command} is a video (use "
                           f".mp4), or its frames as PNG files (frames/####.png)")
    if args.only is not None and not frame_files:
        raise CommandError("--only renders a chunk of the frames: --out names their files "
                           "(frames/####.png), not a video")
    return frame_files


def cmd_turntable(args):
    frame_files = check_out(args)
    check_orbit_options(args)
    chunk = frames_range(args.only, args.frames)
    if args.grease_pencil:                 # a .blend file's drawing: built from its path
        recipe = os.path.abspath(args.recipe)
    elif is_layered_file(args.recipe):     # an .ora or a folder of layers: built from its path
        recipe = os.path.abspath(args.recipe)
    else:
        recipe = load_recipe(args.recipe)
        print_notes(recipe.notes)
    from ..blender.headless import drawn_on, render_turntable  # Blender only when asked for
    try:
        seconds, samples = render_turntable(
            recipe, args.out, args.frames, args.engine, args.size, args.elevation, args.light,
            args.clockwise, args.samples, args.fps,
            progress=lambda line: print(line, flush=True), notes=print_notes,
            grease_pencil=args.grease_pencil, only=chunk if frame_files else None)
    except ValueError as exc:
        raise CommandError(str(exc)) from None
    count = chunk[1] - chunk[0] + 1
    what = f"frames {chunk[0]}–{chunk[1]} of {args.frames}" if count < args.frames else \
        f"{args.frames} frames"
    print(f"turntable: {what} with {args.engine}{on_words(drawn_on(args.engine))}, "
          f"{samples} sample{'s' if samples > 1 else ''} a pixel, in {seconds:.1f} s "
          f"({seconds / count:.2f} s/frame) → {args.out}")


def check_orbit_options(args):
    """CommandError for orbit options (add_orbit_options) no render could take."""
    if args.frames < 2:
        raise CommandError(f"--frames must be at least 2, got {args.frames}")
    if args.size is not None and min(args.size) < 16:
        raise CommandError(f"--size must be at least 16 × 16 pixels, got {args.size}")
    if args.size is not None and any(s % 2 for s in args.size):
        raise CommandError(f"--size must be even in both directions (H.264), got {args.size}")
    if args.size is not None and not video_size_fits(*args.size):
        raise CommandError(f"--size {args.size[0]} {args.size[1]}: larger than a video's frame "
                           f"can be (FFmpeg takes (w + 128)(h + 128) < 2²⁸ pixels: 16254 × "
                           f"16254 at most)")
    if args.size is not None:              # before Blender starts: its frames must fit
        memory.check_video(*args.size, held=memory.base_bytes())
    if args.samples is not None and args.samples < 1:
        raise CommandError(f"--samples must be at least 1, got {args.samples}")
    if args.elevation is not None and not -90 <= args.elevation <= 90:
        raise CommandError(f"--elevation must be in [-90, 90] degrees, got {args.elevation}")


def add_orbit_options(parser):
    """The options of the orbit and its video, shared by `turntable` and `farm submit`."""
    parser.add_argument("--frames", type=int, default=48,
                        help="frames in one orbit (default 48)")
    parser.add_argument("--engine", choices=("eevee", "cycles"), default="cycles",
                        help="cycles (default: CPU, any machine) or eevee (fast with a GPU; "
                        "this needs an OpenGL/EGL driver even in the background)")
    parser.add_argument("--size", type=int, nargs=2, metavar=("W", "H"),
                        help="video size in pixels (default: the shape image's size)")
    parser.add_argument("--elevation", type=float, help="light elevation above the painting "
                        "in degrees (default: where the recipe puts the light)")
    parser.add_argument("--light", help="name of the recipe light to orbit (default: its "
                        "first Sun)")
    parser.add_argument("--clockwise", action="store_true",
                        help="orbit clockwise (seen from the front)")
    parser.add_argument("--samples", type=int, help="render samples per pixel; default: one "
                        "at the shape image's size (the video frames the painting pixel for "
                        "pixel, and one sample at each pixel centre is the exact image), "
                        "antialiased at other sizes (the count is printed)")
    parser.add_argument("--fps", type=int, default=24, help="frames per second of the video "
                        "(default 24)")


def add_parser(sub):
    """Register `turntable` on the command line's subparsers."""
    tt = sub.add_parser("turntable", help="render a light turntable of a recipe to a video",
                        description="The recipe's first Sun (or --light) orbits the painting once, "
                        "starting where the recipe puts it; each frame re-bakes its shadows.")
    tt.add_argument("recipe", help=recipe_help())
    tt.add_argument("--out", required=True, help="video file (.mp4, H.264), or the frames' "
                    "files (frames/####.png: 16-bit PNG, #### the frame's number, each file "
                    "written whole)")
    tt.add_argument("--only", metavar="FIRST-LAST",
                    help="render only these frames of the orbit (1 … --frames) into --out's "
                    "files: a render farm's chunk (farm chunks give the frames a whole "
                    "turntable gives, bit for bit)")
    add_orbit_options(tt)
    tt.add_argument("--grease-pencil", metavar="OBJECT",
                    help="RECIPE is a .blend file: light its Grease Pencil drawing OBJECT as "
                         "Add › From Grease Pencil does (its animation plays while the light "
                         "turns)")
    tt.set_defaults(func=cmd_turntable)
