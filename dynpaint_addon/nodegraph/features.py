"""Features: everything that decides the graph's structure (docs/pipeline.md §12).

One field per *structural* parameter of params.py (named by `Param.feature_name`: shape.kind
→ shape_kind, specular.enabled → specular), generated from the table, plus what the painting's
images and lights decide (size, channels, light kinds, lookup sizes). Equal features build the
same tree, so a painting's tree is rebuilt exactly when its features change — but the size,
which a node tree reads as a value set in place (TREE_VALUES) — and a new structural
parameter needs no code here.

    >>> f = Features(size=(64, 48), shape_kind="height", shadows=True)
    >>> f.shape_kind, f.specular, f.image_channels() >= {"height", "shadow_0"}
    ('height', False, True)
"""
import dataclasses

from .. import params
from ..core.input_rules import albedo_channel, relief_of, silhouette_channel, transparency_branch

# The structural parameters whose Features value depends on the images as well: the value the
# graph needs is resolved from the setting, the channels that have an image and those with alpha.


def _transparency(amount, channels, alpha_channels):
    """k (§11): core.input_rules.transparency_branch of the setting and the map."""
    return transparency_branch(amount, "transparency" in channels)


def _silhouette(source, channels, alpha_channels):
    """The channel whose alpha cuts the painting out (§11), '' for none."""
    return silhouette_channel(source, channels, alpha_channels)


def _relief(relief, channels, alpha_channels):
    """What a normal map's shadows fall from (§6): core.input_rules.relief_of."""
    return relief_of(relief, "shape" in alpha_channels)


RESOLVE = {"transparency.amount": _transparency, "silhouette.source": _silhouette,
           "shadows.relief": _relief}
# fields a built node tree reads as values, set in place (graph.image_size), not its structure
TREE_VALUES = ("size",)
DEFAULT_CHANNELS = frozenset({"shape", "dark", "bright"})
STRUCTURAL = tuple(p for p in params.PARAMS if p.structural)


def _default(param):
    resolve = RESOLVE.get(param.path)
    return resolve(param.default, DEFAULT_CHANNELS, frozenset()) if resolve else param.default


class _FeaturesMethods:
    @classmethod
    def from_params(cls, p, channels, light_kinds, size, alpha_channels=(), sizes=None):
        """Resolve the parameters' structural choices and 'auto' values like core.render.

        channels: the channels that have an image; sizes: {channel: (W, H)} of the
        environment and background (their warped lookups are built texel by texel).
        """
        channels = frozenset(channels)
        alpha_channels = frozenset(alpha_channels)
        sizes = sizes or {}
        values = {}
        for param in STRUCTURAL:
            value = getattr(getattr(p, param.section), param.key)
            resolve = RESOLVE.get(param.path)
            values[param.feature_name] = resolve(value, channels, alpha_channels) \
                if resolve else value
        return cls(size=tuple(size), channels=channels, lights=tuple(light_kinds),
                   lookup_sizes=tuple(sorted((c, tuple(sizes[c])) for c in
                                             ("environment", "background") if c in channels)),
                   **values)

    def key(self, but=()):
        """A stable text form (repr of a frozenset changes order between processes), of every
        field but those in `but`."""
        fields = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                  if f.name not in but}
        return repr({k: (sorted(v) if isinstance(v, frozenset) else v) for k, v in fields.items()})

    def nodes_key(self):
        """key() but the fields a node tree takes as values (TREE_VALUES): equal keys, the
        same nodes and links."""
        return self.key(but=TREE_VALUES)

    @property
    def albedo(self):
        """The one colour image lit as an albedo (§1), '' for a dark and a bright image."""
        return albedo_channel(self.channels)

    @property
    def has_lookups(self):
        return self.transparency != "none"

    @property
    def reflects(self):
        return self.has_lookups and "environment" in self.channels

    @property
    def refracts(self):
        return self.has_lookups and "background" in self.channels

    def image_channels(self):
        """The images the built tree samples (what the add-on must provide)."""
        need = {"height" if self.shape_kind == "height" else "shape"}
        need |= {c for c in ("dark", "bright") if c in self.channels}
        if self.specular:
            need |= {c for c in ("specular_color", "gloss") if c in self.channels}
        if self.has_lookups:
            need |= {c for c in ("transparency",) if c in self.channels}
            need |= {c for c in ("environment",) if self.reflects}
            need |= {c for c in ("background",) if self.refracts}
        if self.silhouette:
            need.add("silhouette")
        if self.silhouette and "background" in self.channels:
            need.add("background_sharp")
        if self.shadows:
            need |= {f"shadow_{i}" for i in range(len(self.lights))}
        if self.marches_relief:
            need.add("relief")
        return need

    @property
    def marches_relief(self):
        """The OSL march reads a normal map's integrated relief (§6 "Relief")."""
        return (self.shadows and self.shadow_source == "osl" and self.shape_kind == "normal"
                and self.shadows_relief == "integrated")


Features = dataclasses.make_dataclass(
    "Features",
    [("size", tuple, dataclasses.field(default=(1, 1))),        # shape image (W, H), pixels
     ("channels", frozenset, dataclasses.field(default=DEFAULT_CHANNELS)),
     ("lights", tuple, dataclasses.field(default=("sun",))),     # kinds, in light order
     ("lookup_sizes", tuple, dataclasses.field(default=())),     # ((channel, (W, H)), …)
     *[(param.feature_name, object, dataclasses.field(default=_default(param)))
       for param in STRUCTURAL]],
    bases=(_FeaturesMethods,), frozen=True)
Features.__module__ = __name__
Features.__doc__ = __doc__.split("\n\n")[0] + " Hashable: equal features, same tree."
