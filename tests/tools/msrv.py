"""Reads `cargo metadata` on stdin; fails when a resolved package declares a newer
`rust-version` than the workspace's own (the minimum Rust the README states)."""
import json
import sys


def key(version):
    return tuple(int(x) for x in version.split("."))


meta = json.load(sys.stdin)
# The workspace's packages (the examples, written as a user's crates, declare none).
ours = {p["rust_version"] for p in meta["packages"] if p["source"] is None and p["rust_version"]}
if len(ours) != 1:
    sys.exit(f"the workspace's packages declare different rust-versions: {sorted(ours)}")
msrv = ours.pop()
newer = [
    f"{p['name']} {p['version']} needs Rust {p['rust_version']}"
    for p in meta["packages"]
    if p.get("rust_version") and key(p["rust_version"]) > key(msrv)
]
if newer:
    sys.exit(f"rust-version {msrv}: " + "; ".join(newer))
print(f"rust-version {msrv}: {len(meta['packages'])} packages keep to it")
