"""Ready-made looks: named sets of parameter values (params.py paths), applied in one go by
the add-on's Look menu (no bpy). `transparency.amount_auto` is the Blender property that
switches the auto value off."""
import copy

LOOKS = {
    "CLASSIC": ("Classic", "Dark image in shadow, bright in full light (t0 = 0, t1 = 1)",
                {"diffuse.t0": 0.0, "diffuse.t1": 1.0, "diffuse.curve": "linear"}),
    "GOOCH": ("Gooch", "Soft wrap-around light from −1 to 1 (technical-illustration look)",
              {"diffuse.t0": -1.0, "diffuse.t1": 1.0, "diffuse.curve": "smoothstep"}),
    "CARTOON": ("Cartoon", "Hard light/shadow step and a crisp highlight",
                {"diffuse.t0": 0.3, "diffuse.t1": 0.3, "specular.enabled": True,
                 "specular.s0": 0.94, "specular.s1": 0.94}),
    "GLASS": ("Glass", "Transparent: refracts the background, reflects the environment",
              {"transparency.amount_auto": False, "transparency.amount": 1.0,
               "refraction.mode": "physical", "refraction.ior": 1.5, "fresnel.mode": "physical",
               "specular.enabled": True, "specular.s0": 0.92, "specular.s1": 1.0}),
    "MIRROR": ("Mirror", "Reflects the environment everywhere (art Fresnel at total reflection)",
               {"transparency.amount_auto": False, "transparency.amount": 1.0,
                "fresnel.mode": "art", "fresnel.kappa": 1.0, "reflection.distance": 0.05}),
}


def with_look(p, key):
    """A copy of the parameters `p` (a params namespace) with look `key` applied; the Blender
    switch `transparency.amount_auto` is implied by the amount the look sets."""
    p = copy.deepcopy(p)
    for path, value in LOOKS[key][2].items():
        section, name = path.split(".")
        if name != "amount_auto":
            setattr(getattr(p, section), name, value)
    return p
