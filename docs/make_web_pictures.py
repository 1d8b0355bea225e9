"""Pictures of the exported web page for README.md and docs/web.md (issue 17): the portrait
sample exported by `export-web`, opened in headless Chromium (software WebGL2), before and
after a drag moves its key light to the left and the wheel lowers it; and (issue 42) the
Grease Pencil sample walk's page, lit in background Blender, paused on a frame of its walk.

    .venv/bin/python docs/make_web_pictures.py            # ≈ 40 s; writes docs/img/web/*.png

Screenshots hold the browser's own text rendering, so they differ by a few pixels between
machines' fonts: they are pictures, not test references (the page's pixels are tested in
tests/blender/test_web_page.py against the numpy core).
"""
import argparse
import os
import sys
import tempfile

DOCS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(DOCS))

from dynpaint_addon.blender.headless import grease_pencil_page        # noqa: E402
from dynpaint_addon.inputs.recipe import load_images, load_recipe      # noqa: E402
from dynpaint_addon.inputs.samples import recipe_path                  # noqa: E402
from testkit.chromium import Chromium                # noqa: E402
from dynpaint_addon.web.page import page_data, write_page       # noqa: E402

WINDOW = (960, 720)
WALK_PX = 640           # the walk's layers drawn this wide (its page fits the window)


def canvas_point(page, fx, fy):
    left, top, w, h = page.box("painting")
    return left + fx * w, top + fy * h


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(DOCS, "img", "web"), help="picture folder")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    recipe = load_recipe(recipe_path("portrait"))
    data, _ = page_data(load_images(recipe), recipe.lights, recipe.params, title=recipe.name,
                        credits="Height map rendered from Blender's Suzanne; painted dark and "
                                "bright images (sample_scenes/portrait)")
    with tempfile.TemporaryDirectory() as folder, Chromium() as browser:
        path = os.path.join(folder, "portrait.html")
        write_page(path, data)
        page = browser.open("file://" + path, *WINDOW)
        page.evaluate("window.dynamicPainting.ready")
        page.screenshot(os.path.join(args.out, "page.png"))
        page.mouse("pressed", *canvas_point(page, 0.5, 0.5))
        page.mouse("moved", *canvas_point(page, 0.08, 0.3))
        page.mouse("released", *canvas_point(page, 0.08, 0.3))
        page.wheel(*canvas_point(page, 0.5, 0.5), 500)          # lower: longer shadows
        page.evaluate("new Promise(done => requestAnimationFrame(() => "
                      "requestAnimationFrame(done)))")
        page.screenshot(os.path.join(args.out, "dragged.png"))
        walk = load_recipe(recipe_path("walk"))
        data, _ = grease_pencil_page(walk, width=WALK_PX, title=walk.name, credits=walk.credits)
        path = os.path.join(folder, "walk.html")
        write_page(path, data)
        page = browser.open("file://" + path, *WINDOW)
        page.evaluate("window.dynamicPainting.ready")
        page.evaluate("window.dynamicPainting.setFrame(8)")
        page.wait_for("!window.dynamicPainting.state.dirty && "
                      "window.dynamicPainting.state.drawScale === 1")
        page.screenshot(os.path.join(args.out, "walk.png"))
    print(f"wrote {args.out}/page.png, dragged.png, walk.png")


if __name__ == "__main__":
    main()
