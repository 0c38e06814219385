"""Count the public items of the fringe library crate from rustdoc's JSON (hidden items
included): every item of the local crate whose visibility is `public` and that is reachable
by a path from the crate root (rustdoc's `paths` table, kind not a module-level `use`), plus
the public fields, variants' fields and associated items of those. A throw-away measurement
for issue 16; not used by the build or the tests.

Run (nightly rustdoc; from the repository root):
    cargo +nightly rustdoc --lib -- -Z unstable-options --output-format json --document-hidden-items
    python3 tools/count_pub_items.py "$CARGO_TARGET_DIR/doc/fringe.json"
"""
import collections
import json
import sys

doc = json.load(open(sys.argv[1]))
index = doc["index"]
root = doc["root"]

# Walk from the root module through public modules, collecting reachable public items.
seen = set()
stack = [root]
kinds = collections.Counter()
while stack:
    i = stack.pop()
    if i in seen or str(i) not in index:
        continue
    seen.add(i)
    item = index[str(i)]
    if item.get("crate_id", 0) != 0:
        continue
    vis = item.get("visibility")
    if i != root and vis != "public" and vis != "default":
        continue
    inner = item["inner"]
    (kind, body), = inner.items()
    if i != root and kind != "use":
        kinds[kind] += 1
    children = []
    if kind == "module":
        children = body["items"]
    elif kind == "use":
        if body.get("id") is not None and not body.get("is_glob"):
            children = [body["id"]]
    elif kind == "struct":
        k = body["kind"]
        if "plain" in k:
            children = k["plain"]["fields"]
        elif "tuple" in k:
            children = [f for f in k["tuple"] if f is not None]
        children += body["impls"]
    elif kind == "enum":
        children = body["variants"] + body["impls"]
    elif kind == "variant":
        k = body["kind"]
        if isinstance(k, dict) and "struct" in k:
            children = k["struct"]["fields"]
    elif kind == "impl":
        if body.get("trait") is None and not body.get("is_synthetic"):
            children = body["items"]
        kinds["impl"] -= 1  # impl blocks themselves are not items a user names
    elif kind == "trait":
        children = body["items"]
    stack.extend(children)

del kinds["impl"]
for k, n in sorted(kinds.items()):
    print(f"{k:14} {n}")
print(f"{'total':14} {sum(kinds.values())}")
