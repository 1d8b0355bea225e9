"""`dynpaint demo`: the built-in test painting rendered by the numpy core (no
Blender needed)."""
import time

from ..core.pipeline import render
from ..inputs.imageio import write_render
from ..inputs.testpainting import builtin_images, builtin_recipe


def cmd_demo(args):
    recipe = builtin_recipe()
    t = time.perf_counter()
    result = render(builtin_images(args.size), recipe.lights, recipe.params)
    ms = (time.perf_counter() - t) * 1000
    write_render(args.out, result.rgba)
    print(f"rendered the built-in test painting ({args.size}×{args.size}, numpy core, "
          f"cos-θ shadows, 2 lights) in {ms:.0f} ms → {args.out}")


def add_parser(sub):
    """Register `demo` on the command line's subparsers."""
    d = sub.add_parser("demo", help="render the built-in test painting with the numpy core (no "
                       "Blender needed; the README's main job is `turntable portrait`)",
                       description="Render the built-in test painting (a normal map, two "
                       "lights, cos-θ shadows) with the numpy core to an image: a check that "
                       "the math runs, with no file and no Blender.")
    d.add_argument("--out", default="out/demo.png", help="output image (default out/demo.png)")
    d.add_argument("--size", type=int, default=256, help="size in pixels (default 256)")
    d.set_defaults(func=cmd_demo)
