"""Write the shipped example OSL shaders (generated; the add-on generates its own per painting).

    .venv/bin/python shaders_osl/make_shaders.py

Each is the whole pipeline (pipeline.md §2–§11) for one set of features, generated from the
graph description by dynpaint_addon/nodegraph/osl_codegen.py, with the cos-θ march of
dynpaint_addon/nodegraph/snippets/shared/cos_theta.h inside the shader.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

from dynpaint_addon.nodegraph import osl_codegen  # noqa: E402
from dynpaint_addon.nodegraph.pipeline_graph import Features, describe  # noqa: E402

SHADERS = {
    "dynamic_painting_height_shadows.osl": Features(
        size=(1024, 1024), shape_kind="height", lights=("sun", "point"), shadows=True,
        specular=True, shadow_source="osl"),
    "dynamic_painting_normal_shadows.osl": Features(
        size=(1024, 1024), shape_kind="normal", lights=("sun",), shadows=True,
        shadow_source="osl"),
}


def sources():
    return {name: osl_codegen.generate(describe(f), f, march=True) for name, f in SHADERS.items()}


def main():
    for name, src in sources().items():
        with open(os.path.join(HERE, name), "w", encoding="utf-8") as fh:
            fh.write(src)
        print(f"wrote {name}")


if __name__ == "__main__":
    main()
