"""Fails when the workspace's rust-version is older than a dependency's.

Reads `cargo metadata` JSON on stdin. Every package of the resolved tree
that declares a rust-version must not need a newer compiler than the one
the workspace promises.
"""
import json
import sys


def version(v):
    parts = [int(x) for x in v.split(".")]
    return tuple(parts + [0] * (3 - len(parts)))


meta = json.load(sys.stdin)
members = set(meta["workspace_members"])
ours = {p["rust_version"] for p in meta["packages"] if p["id"] in members}
if len(ours) != 1 or None in ours:
    sys.exit(f"workspace members declare rust-version {sorted(map(str, ours))}: expected one value")
ours = ours.pop()
worst = max(
    ((p["rust_version"], p["name"], p["version"]) for p in meta["packages"]
     if p["id"] not in members and p.get("rust_version")),
    key=lambda t: version(t[0]),
)
if version(worst[0]) > version(ours):
    sys.exit(f"rust-version {ours} is older than {worst[1]} {worst[2]} needs ({worst[0]})")
print(f"rust-version {ours}; newest requirement in the tree: {worst[1]} {worst[2]} ({worst[0]})")
