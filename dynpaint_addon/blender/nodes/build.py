"""Turn a Graph (graph.py) into Blender nodes: shared by the material and the compositor group.

`build(tree, graph, backend)` creates the ordinary nodes (the same classes in shader and
compositor trees), instantiates sub-graphs as node groups (built once per name and tree type),
frames each section and lays the columns out left to right, so an artist who opens the editor
can follow it. The `backend` object supplies the few backend-specific pieces (graph.py): UV,
image lookups, parameters, lights and the output.
"""
import hashlib

import bpy

from ...nodegraph.graph import FLOAT, Ref

SOCKET_TYPES = {FLOAT: "NodeSocketFloat", "VECTOR": "NodeSocketVector"}
COLUMN_WIDTH, ROW_HEIGHT = 220, 190
GROUP_VERSION_KEY = "dp_group_signature"
BACKEND_OPS = ("uv", "size", "sample", "param", "light", "output")


def find_socket(sockets, key):
    """A node socket by index, identifier or name (identifiers disambiguate Mix/Map Range)."""
    if isinstance(key, int):
        return sockets[key]
    for s in sockets:
        if s.identifier == key:
            return s
    return sockets[key]


def set_constant(socket, value):
    """A constant into a socket: vectors and colours padded (alpha 1), a scalar spread over
    a colour's RGB; written only where it differs (assign)."""
    current = socket.default_value
    if hasattr(current, "__len__"):
        n = len(current)
        vec = tuple(value) if isinstance(value, (tuple, list)) else (value,) * min(n, 3)
        value = (vec + (1.0,) * n)[:n]
        current = tuple(current)
    if current != value:
        socket.default_value = value


def assign(node, key, value):
    """node.key = value where it differs. Every write through RNA updates the whole tree
    (about 1 µs per node in it: building a tree is quadratic in its size), and of a
    material's 214 settings and 146 constants 125 and 54 are the node's defaults already."""
    if getattr(node, key) != value:
        setattr(node, key, value)


def link_or_set(tree, value, socket):
    """Connect an output socket, or set a constant."""
    if isinstance(value, bpy.types.NodeSocket):
        tree.links.new(value, socket)
    else:
        set_constant(socket, value)


def _signature(graph):
    """A stable text form of a sub-graph, so a stored node group is rebuilt when it changes."""
    parts = []
    for n in graph.nodes:
        props = {k: (v.name if k == "graph" else v) for k, v in sorted(n.props.items())}
        parts.append(f"{n.op}{props}{sorted(n.inputs.items(), key=str)}")
    text = "|".join(parts + [str(graph.inputs), str(graph.outputs)])
    return hashlib.sha1(text.encode()).hexdigest()[:16]


def node_group(graph, tree_type, prefix=""):
    """The node group of a sub-graph for this tree type, built (or rebuilt) when needed."""
    name = prefix + graph.name
    sig = _signature(graph)
    ng = bpy.data.node_groups.get(name)
    if ng is not None and (ng.bl_idname != tree_type or ng.get(GROUP_VERSION_KEY) != sig):
        ng.name = name + ".old"       # keep users working until they are rebuilt
        ng = None
    if ng is None:
        ng = bpy.data.node_groups.new(name, tree_type)
        for sock_name, kind in graph.inputs:
            ng.interface.new_socket(sock_name, in_out="INPUT", socket_type=SOCKET_TYPES[kind])
        for sock_name, kind in graph.outputs:
            ng.interface.new_socket(sock_name, in_out="OUTPUT", socket_type=SOCKET_TYPES[kind])
        build(ng, graph, GroupBackend(prefix))
        ng[GROUP_VERSION_KEY] = sig
    return ng


class GroupBackend:
    """Inside node groups only group inputs/outputs and nested groups occur."""

    def __init__(self, prefix=""):
        self.prefix = prefix


def build(tree, graph, backend):
    """Create graph's nodes in `tree` (which should be empty) and link them.

    → {graph node id: [bpy nodes]} (the last one is the node itself, the others its helpers)
    """
    made = {}        # graph node id → bpy node
    outputs = {}     # graph node id → {output key: socket} for pseudo nodes

    def out_socket(ref):
        if ref.node in outputs:
            return outputs[ref.node][ref.output]
        return find_socket(made[ref.node][-1].outputs, ref.output)

    def connect(node, key, value):
        sock = find_socket(node.inputs, key)
        if isinstance(value, Ref):          # (a backend may answer a pseudo node by a number)
            link_or_set(tree, out_socket(value), sock)
        elif value is not None:
            set_constant(sock, value)

    for n in graph.nodes:
        if n.op == "dp.group_input":
            node = tree.nodes.new("NodeGroupInput")
            outputs[n.id] = {name: node.outputs[name] for name, _ in graph.inputs}
        elif n.op == "dp.group_output":
            node = tree.nodes.new("NodeGroupOutput")
            for key, value in n.inputs.items():
                connect(node, key, value)
        elif n.op == "dp.group":
            node = tree.nodes.new(tree.bl_idname.replace("Tree", "Group"))
            node.node_tree = node_group(n.props["graph"], tree.bl_idname, backend.prefix)
            for key, value in n.inputs.items():
                connect(node, key, value)
        elif n.op.startswith("dp."):
            handler = getattr(backend, n.op[3:])
            resolved = {k: (out_socket(v) if isinstance(v, Ref) else v) for k, v in n.inputs.items()}
            nodes, outs = handler(tree, n, resolved)
            outputs[n.id] = outs
            node = nodes[-1] if nodes else None    # e.g. a socket of a shared input node
        else:
            node = tree.nodes.new(n.op)
            for key, value in n.props.items():
                assign(node, key, value)
            for key, value in n.inputs.items():
                connect(node, key, value)
        if n.label and node is not None:
            node.label = n.label
        made[n.id] = nodes if n.op.startswith("dp.") and n.op[3:] in BACKEND_OPS else [node]
    layout(tree, graph, made)
    return made


def layout(tree, graph, made):
    """Columns by longest path from the inputs; sections as labelled frames."""
    depth = {}
    for n in graph.nodes:
        deps = [v.node for v in n.inputs.values() if isinstance(v, Ref)]
        depth[n.id] = 1 + max((depth[d] for d in deps), default=-1)
    sections = list(dict.fromkeys(n.section for n in graph.nodes))
    frames = {}
    for title in sections:
        if title:
            frame = tree.nodes.new("NodeFrame")
            frame.label = title
            frame.label_size = 16
            frames[title] = frame
    rows, where = {}, {}          # node pointer → its planned location
    for n in sorted(graph.nodes, key=lambda n: (sections.index(n.section), n.id)):
        col = depth[n.id]
        row = rows.get(col, 0)
        rows[col] = row + 1
        nodes = made[n.id]
        for k, node in enumerate(reversed(nodes)):   # a backend's helper nodes sit to the left
            if n.section in frames:
                node.parent = frames[n.section]
            where[node.as_pointer()] = (col * COLUMN_WIDTH - k * 170, -row * ROW_HEIGHT)
    others = (n for n in tree.nodes if n.as_pointer() not in where and n.bl_idname != "NodeFrame")
    for k, node in enumerate(others):
        where[node.as_pointer()] = (-2 * COLUMN_WIDTH, -k * ROW_HEIGHT)   # shared inputs, far left
    # All at once: each node.location set updates the whole tree (O(nodes): 0.4 ms a node at
    # 300 nodes), foreach_set does not — the layout was half of a rebuild's time.
    flat = [0.0] * (2 * len(tree.nodes))
    tree.nodes.foreach_get("location", flat)
    for i, node in enumerate(tree.nodes):
        flat[2 * i:2 * i + 2] = where.get(node.as_pointer(), flat[2 * i:2 * i + 2])
    tree.nodes.foreach_set("location", flat)


def count_nodes(tree, seen=None):
    """Nodes of a built tree plus those of its node groups (each group once), frames excluded:
    the node count §12 compares."""
    seen = set() if seen is None else seen
    total = 0
    for node in tree.nodes:
        if node.bl_idname == "NodeFrame":
            continue
        total += 1
        sub = getattr(node, "node_tree", None)
        if sub is not None and sub.name not in seen:
            seen.add(sub.name)
            total += count_nodes(sub, seen)
    return total
