"""An independent full check of the graph rules, recomputed from scratch (it does not trust the
graph's incremental bookkeeping), for tests."""

import numpy as np

from dsr_graph.model.binary import equal
from dsr_graph.model.values import coerce

RT = "RT"


def assert_invariants(graph):
    nodes = {n.id: n for n in graph.nodes()}
    names = [n.name for n in nodes.values()]
    assert len(names) == len(set(names)), "node names must be unique"
    for n in nodes.values():
        assert graph.find(n.name) is n and graph.find(n.id) is n
        assert n.type in graph.vocabulary.node_types
        assert n.version >= 1
        for k, v in n.attrs.items():
            assert equal(coerce(graph.vocabulary.attributes[k], v), v)
    parent = {}
    children = {}
    for e in graph.edges():
        assert e.src in nodes and e.dst in nodes, f"dangling {e}"
        assert e.src != e.dst, f"self-loop {e}"
        assert e.type in graph.vocabulary.edge_types
        assert e.version >= 1
        if e.type == RT:
            assert e.rt is not None and e.rt.shape == (4, 4)
            r = e.rt[:3, :3]
            assert np.allclose(r.T @ r, np.eye(3), atol=1e-6) and abs(np.linalg.det(r) - 1) < 1e-6
            assert np.allclose(e.rt[3], [0, 0, 0, 1])
            assert e.dst not in parent, f"two RT parents for {e.dst}"
            parent[e.dst] = e.src
            children.setdefault(e.src, []).append(e.dst)
        else:
            assert e.rt is None
    geometric = set(parent) | set(children)
    roots = [n for n in geometric if n not in parent]
    assert len(roots) <= 1, f"RT forest with roots {roots}"
    for n in geometric:  # every geometric node reaches the root without a cycle
        seen = set()
        while n in parent:
            assert n not in seen, "RT cycle"
            seen.add(n)
            n = parent[n]
        assert n == roots[0]
    for n in nodes.values():
        assert graph.is_geometric(n.id) == (n.id in geometric)
