#!/usr/bin/env python3
"""Checks the workspace's rust-version: set on every package, and not below the rust-version
of any dependency in the lock file (cargo would refuse to build them with an older compiler)."""
import json
import subprocess
import sys

meta = json.loads(subprocess.check_output(
    ["cargo", "metadata", "--format-version", "1", "--locked"], text=True))
members = set(meta["workspace_members"])


def parse(v):
    return tuple(int(x) for x in (v.split(".") + ["0", "0"])[:3])


ours = {}
for p in meta["packages"]:
    if p["id"] in members:
        if not p.get("rust_version"):
            sys.exit(f"rust-version missing in package {p['name']}")
        ours[p["name"]] = parse(p["rust_version"])
msrv = min(ours.values())
worst = max(((parse(p["rust_version"]), p["name"], p["version"]) for p in meta["packages"]
             if p["id"] not in members and p.get("rust_version")), default=((0, 0, 0), "", ""))
print(f"workspace rust-version {'.'.join(map(str, msrv))}; highest dependency requirement "
      f"{'.'.join(map(str, worst[0]))} ({worst[1]} {worst[2]})")
if worst[0] > msrv:
    sys.exit("a dependency needs a newer Rust than the workspace's rust-version")
