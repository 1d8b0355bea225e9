"""Pictures of the exported web page for README.md and docs/web.md (issue 17): the portrait
sample exported by `export-web`, opened in headless Chromium (software WebGL2), before and
after a drag moves its key light to the left and the wheel lowers it.

    .venv/bin/python docs/make_web_pictures.py            # ≈ 5 s; writes docs/img/web/*.png

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

from dynpaint_addon.inputs.recipe import load_images, load_recipe      # noqa: E402
from dynpaint_addon.inputs.samples import recipe_path                  # noqa: E402
from testkit.chromium import Chromium                # noqa: E402
from dynpaint_addon.web.page import page_data, write_page       # noqa: E402

WINDOW = (960, 720)


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
    print(f"wrote {args.out}/page.png, dragged.png")


if __name__ == "__main__":
    main()
