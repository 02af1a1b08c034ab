#!/usr/bin/env python3
"""The public surface of deploywatch-core, one line per item and path.

    scripts/public-api.py            print the listing
    scripts/public-api.py --count [--before REV]
                                     print the number of lines of the listing,
                                     in all and by kind (a Markdown table);
                                     with --before, the same of the core at
                                     git revision REV beside it (REV's tree
                                     extracted to a temporary folder, listed
                                     by this script)
    scripts/public-api.py --write    write it to core/public-api.txt
    scripts/public-api.py --check    compare with core/public-api.txt; exit 1
                                     with a diff when they differ

It runs rustdoc's JSON output on the core (stable toolchain; RUSTC_BOOTSTRAP=1
unlocks `-Z unstable-options`, as scripts/fuzz.sh does for cargo-fuzz):

    RUSTC_BOOTSTRAP=1 cargo rustdoc -p deploywatch-core --lib --locked \\
        --features hal,defmt -- -Z unstable-options --output-format json

with every feature a user can turn on (`hal`, `defmt`): the surface a
firmware or host crate can link. It then walks the crate from its root, the
way a user's `use` does: public modules, and `pub use` re-exports (globs
too) of the core's own items. One line per public item reachable by a path,
`KIND PATH`:

    mod, struct, enum, union, trait, fn, const, static, type, macro  (items)
    field, variant                        (public fields, enum variants)
    method, assoc const, assoc type       (inherent impls; a trait's items)
    re-export PATH = SOURCE               (a `pub use` of another crate's item)

An item reachable by two paths gives two lines: the listing shows where the
surface is not one path per item, and `--check` fails on it too (the core's
rule: one path per item). Trait implementations (derived or written,
auto traits, blankets) are left out: the listing is of paths, as
cargo-public-api's items are; rustdoc's pages show the impls. The listing is
sorted, so it does not depend on the order of the JSON.

The build goes to its own folder, `public-api/` in the target directory
(CARGO_TARGET_DIR is honoured; the JSON is read from its `doc/`): build
scripts that look at RUSTC_BOOTSTRAP (proc-macro2's) would otherwise run
again for the next ordinary build in the shared folder, and everything
above them with it (the whole test build, in the CI lane after this one).
Python 3, standard library only.
"""
import collections
import difflib
import json
import os
import subprocess
import sys
import tarfile
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LISTING = os.path.join(ROOT, "core", "public-api.txt")
CRATE = "deploywatch_core"
FEATURES = "hal,defmt"


def rustdoc_json(root=ROOT):
    """Builds the core's rustdoc JSON (of the workspace at `root`) and
    returns it parsed."""
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    if not os.path.isabs(target):
        target = os.path.join(ROOT, target)
    target = os.path.join(target, "public-api")
    env = dict(os.environ, RUSTC_BOOTSTRAP="1", CARGO_TARGET_DIR=target)
    cmd = ["cargo", "rustdoc", "-p", "deploywatch-core", "--lib", "--locked",
           "--features", FEATURES, "--",
           "-Z", "unstable-options", "--output-format", "json"]
    r = subprocess.run(cmd, cwd=root, env=env, stdout=subprocess.DEVNULL,
                       stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stderr)
        sys.exit(f"public-api.py: `{' '.join(cmd)}` failed")
    with open(os.path.join(target, "doc", CRATE + ".json"), encoding="utf-8") as f:
        return json.load(f)


def kind_of(item):
    inner = item["inner"]
    return next(iter(inner)) if isinstance(inner, dict) else inner


class Walker:
    def __init__(self, doc):
        self.index = doc["index"]
        self.root = doc["root"]
        self.lines = set()
        self.paths = {}  # item id -> the paths it is reachable by

    def item(self, ident):
        return self.index.get(str(ident))

    def emit(self, kind, path):
        self.lines.add((path, kind))

    def walk_module(self, mod_id, prefix, stack):
        """Every public item of a module (or of a glob's source) under prefix."""
        if mod_id in stack:
            return
        stack = stack | {mod_id}
        for ident in self.item(mod_id)["inner"]["module"]["items"]:
            it = self.item(ident)
            if it is None or it["visibility"] != "public":
                continue
            if kind_of(it) == "use":
                self.walk_use(it, prefix, stack)
            else:
                self.walk_item(it, f"{prefix}::{it['name']}", stack)

    def walk_use(self, it, prefix, stack):
        use = it["inner"]["use"]
        target = self.item(use["id"]) if use["id"] is not None else None
        local = target is not None and target["crate_id"] == 0
        if use["is_glob"]:
            if local and kind_of(target) == "module":
                self.walk_module(target["id"], prefix, stack)
            elif local and kind_of(target) == "enum":
                for v in target["inner"]["enum"]["variants"]:
                    self.walk_item(self.item(v), f"{prefix}::{self.item(v)['name']}", stack)
            else:
                self.emit("re-export", f"{prefix}::* = {use['source']}::*")
            return
        path = f"{prefix}::{use['name']}"
        if local:
            self.walk_item(target, path, stack)
        else:
            self.emit("re-export", f"{path} = {use['source']}")

    def walk_item(self, it, path, stack):
        self.paths.setdefault(it["id"], set()).add(path)
        kind = kind_of(it)
        inner = it["inner"][kind] if isinstance(it["inner"], dict) else None
        if kind == "module":
            self.emit("mod", path)
            self.walk_module(it["id"], path, stack)
        elif kind == "struct":
            self.emit("struct", path)
            k = inner["kind"]
            if isinstance(k, dict) and "plain" in k:
                self.fields(k["plain"]["fields"], path)
            elif isinstance(k, dict) and "tuple" in k:
                for i, f in enumerate(k["tuple"]):
                    if f is not None and self.item(f)["visibility"] == "public":
                        self.emit("field", f"{path}::{i}")
            self.inherent(inner["impls"], path)
        elif kind == "union":
            self.emit("union", path)
            self.fields(inner["fields"], path)
            self.inherent(inner["impls"], path)
        elif kind == "enum":
            self.emit("enum", path)
            for v in inner["variants"]:
                self.walk_item(self.item(v), f"{path}::{self.item(v)['name']}", stack)
            self.inherent(inner["impls"], path)
        elif kind == "variant":
            self.emit("variant", path)
            k = inner["kind"]
            if isinstance(k, dict) and "struct" in k:
                self.fields(k["struct"]["fields"], path)
        elif kind == "trait":
            self.emit("trait", path)
            for m in inner["items"]:
                self.member(self.item(m), path)
        elif kind == "function":
            self.emit("fn", path)
        elif kind == "constant":
            self.emit("const", path)
        elif kind == "static":
            self.emit("static", path)
        elif kind == "type_alias":
            self.emit("type", path)
        elif kind in ("macro", "proc_macro"):
            self.emit("macro", path)
        elif kind == "use":
            self.walk_use(it, path.rsplit("::", 1)[0], stack)
        else:
            self.emit(kind, path)

    def fields(self, ids, path):
        for f in ids:
            fi = self.item(f)
            if fi is not None and fi["visibility"] == "public":
                self.emit("field", f"{path}::{fi['name']}")

    def inherent(self, impl_ids, path):
        for i in impl_ids:
            imp = self.item(i)
            if imp is None:
                continue
            body = imp["inner"]["impl"]
            if body["trait"] is not None or body["is_synthetic"] or body["blanket_impl"]:
                continue
            for m in body["items"]:
                mi = self.item(m)
                if mi is not None and mi["visibility"] == "public":
                    self.member(mi, path)

    def member(self, mi, path):
        kind = kind_of(mi)
        name = {"function": "method", "assoc_const": "assoc const",
                "assoc_type": "assoc type"}.get(kind, kind)
        self.emit(name, f"{path}::{mi['name']}")


def listing(root=ROOT):
    """The listing's lines, and the items reachable by more than one path."""
    doc = rustdoc_json(root)
    w = Walker(doc)
    w.walk_module(doc["root"], CRATE, frozenset())
    lines = [f"{kind} {path}" for path, kind in sorted(w.lines)]
    twice = sorted(sorted(p) for p in w.paths.values() if len(p) > 1)
    return lines, twice


def listing_at(rev):
    """The listing of the core at git revision `rev`: its tree extracted
    with `git archive` to a temporary folder (the checkout is untouched)."""
    with tempfile.TemporaryDirectory(prefix="public-api-") as tmp:
        archive = os.path.join(tmp, "tree.tar")
        subprocess.run(["git", "archive", "--format=tar", "-o", archive, rev],
                       cwd=ROOT, check=True)
        tree = os.path.join(tmp, "tree")
        with tarfile.open(archive) as t:
            t.extractall(tree, filter="data")
        if "CARGO_TARGET_DIR" not in os.environ:
            # The checkout's target folder (its public-api/): the
            # dependencies are built once.
            os.environ["CARGO_TARGET_DIR"] = os.path.join(ROOT, "target")
        return listing(tree)[0]


def kinds(lines):
    """Lines of the listing by kind (`assoc const` is one kind)."""
    return collections.Counter(l.rsplit(" ", 1)[0] if " = " not in l else "re-export"
                               for l in lines)


def count_table(lines, before):
    """The counts as a Markdown table: by kind, then in all; the listing at
    revision `before` (a pair: the revision, its lines) in a column first
    when given."""
    cols = ([f"at `{before[0]}`"] if before else []) + ["this tree"]
    counts = ([kinds(before[1])] if before else []) + [kinds(lines)]
    totals = ([len(before[1])] if before else []) + [len(lines)]
    rows = [f"Lines of the listing of deploywatch-core's public surface (features "
            f"{FEATURES}): one per item and path, trait impls left out.", "",
            "| kind | " + " | ".join(cols) + " |", "|---|" + "---:|" * len(cols)]
    for k in sorted(set().union(*counts)):
        rows.append(f"| {k} | " + " | ".join(f"{c[k]:,}" for c in counts) + " |")
    rows.append("| **all** | " + " | ".join(f"**{t:,}**" for t in totals) + " |")
    return "\n".join(rows) + "\n"


def main(argv):
    modes = {"--count", "--write", "--check"}
    before = None
    if len(argv) == 3 and argv[0] == "--count" and argv[1] == "--before":
        before = argv[2]
        argv = argv[:1]
    if len(argv) > 1 or (argv and argv[0] not in modes):
        sys.exit(__doc__)
    lines, twice = listing()
    text = "".join(l + "\n" for l in lines)
    mode = argv[0] if argv else None
    if mode is None:
        sys.stdout.write(text)
    elif mode == "--count":
        old = (before, listing_at(before)) if before else None
        sys.stdout.write(count_table(lines, old))
    elif mode == "--write":
        with open(LISTING, "w", encoding="utf-8") as f:
            f.write(text)
        print(f"public-api.py: wrote {len(lines)} lines to core/public-api.txt")
    else:
        old = open(LISTING, encoding="utf-8").read() if os.path.exists(LISTING) else ""
        for paths in twice:
            print("public-api.py: one item, two paths: " + ", ".join(paths), file=sys.stderr)
        if twice:
            print("public-api.py: the core gives each public item one path; "
                  "make one of them private or drop the re-export", file=sys.stderr)
            return 1
        if old == text:
            print(f"public-api.py: core/public-api.txt is up to date ({len(lines)} lines)")
            return 0
        sys.stdout.writelines(difflib.unified_diff(
            old.splitlines(True), text.splitlines(True),
            "core/public-api.txt (committed)", "core/public-api.txt (this tree)"))
        print("public-api.py: the core's public surface changed; if that is meant, "
              "run `python3 scripts/public-api.py --write` and commit core/public-api.txt",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
