#!/usr/bin/env python3
"""Copies a subset of the IPC classical benchmarks out of a checkout (or a bare git
directory) of github.com/aibasel/downward-benchmarks: one formulation of every IPC
1998-2014 satisficing-track domain, the N smallest problems of each (by file size),
with --median also the problem of median size and with --largest K the K largest,
each problem with its domain file.

    python3 ipc_subset.py SOURCE DEST [--per-domain N] [--median] [--largest K]

SOURCE is a work tree or a bare git directory (read at HEAD). DEST gets one folder per
domain, holding `domain.pddl` (or one domain file per problem, named as in SOURCE) and
the problems. `sim-host bench-pddl DEST` runs on the result.
"""
import argparse
import os
import subprocess
import sys

# One formulation per domain: IPC 1998-2004 (STRIPS and ADL), 2006, and the
# satisficing tracks of 2008, 2011 and 2014.
DOMAINS = """
airport assembly blocks depot driverlog freecell grid gripper logistics00 logistics98
miconic miconic-fulladl miconic-simpleadl movie mprime mystery optical-telegraphs
philosophers pipesworld-notankage psr-large psr-middle psr-small satellite schedule
zenotravel
openstacks pathways pipesworld-tankage rovers storage tpp trucks
elevators-sat08-strips openstacks-sat08-adl openstacks-sat08-strips parcprinter-08-strips
pegsol-08-strips scanalyzer-08-strips sokoban-sat08-strips transport-sat08-strips
woodworking-sat08-strips
barman-sat11-strips elevators-sat11-strips floortile-sat11-strips nomystery-sat11-strips
openstacks-sat11-strips parcprinter-sat11-strips parking-sat11-strips pegsol-sat11-strips
scanalyzer-sat11-strips sokoban-sat11-strips tidybot-sat11-strips transport-sat11-strips
visitall-sat11-strips woodworking-sat11-strips
cavediving-14-adl citycar-sat14-adl maintenance-sat14-adl barman-sat14-strips
childsnack-sat14-strips floortile-sat14-strips ged-sat14-strips hiking-sat14-strips
openstacks-sat14-strips parking-sat14-strips tetris-sat14-strips thoughtful-sat14-strips
transport-sat14-strips visitall-sat14-strips
""".split()


def is_domain_file(name):
    return "domain" in name


def domain_for(problem, names):
    """The domain file of a problem, by the naming conventions of the collection."""
    for candidate in ("domain_" + problem, "domain-" + problem, problem[:3] + "-domain.pddl", "domain.pddl"):
        if candidate in names:
            return candidate
    return None


class Tree:
    def __init__(self, source):
        self.bare = not os.path.isdir(os.path.join(source, "blocks"))
        self.source = source

    def listing(self, folder):
        """(name, size) of the files in a folder."""
        if not self.bare:
            path = os.path.join(self.source, folder)
            return [(n, os.path.getsize(os.path.join(path, n))) for n in os.listdir(path)]
        out = subprocess.run(["git", "--git-dir", self.source, "ls-tree", "-l", "HEAD:" + folder],
                             check=True, capture_output=True, text=True).stdout
        rows = []
        for line in out.splitlines():
            meta, name = line.split("\t", 1)
            rows.append((name, int(meta.split()[3])))
        return rows

    def read(self, folder, name):
        if not self.bare:
            with open(os.path.join(self.source, folder, name), "rb") as f:
                return f.read()
        r = subprocess.run(["git", "--git-dir", self.source, "cat-file", "blob", "HEAD:%s/%s" % (folder, name)],
                           capture_output=True)
        return r.stdout if r.returncode == 0 else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source")
    ap.add_argument("dest")
    ap.add_argument("--per-domain", type=int, default=5, help="the N smallest problems of each domain")
    ap.add_argument("--median", action="store_true", help="also the problem of median size")
    ap.add_argument("--largest", type=int, default=0, metavar="K", help="also the K largest problems")
    args = ap.parse_args()
    tree = Tree(args.source)
    total = 0
    for d in DOMAINS:
        files = dict(tree.listing(d))
        problems = sorted((size, name) for name, size in files.items()
                          if name.endswith(".pddl") and not is_domain_file(name))
        chosen = problems[:args.per_domain]
        if args.median and problems:
            chosen.append(problems[(len(problems) - 1) // 2])
        if args.largest > 0:
            chosen.extend(problems[-args.largest:])
        kept = 0
        seen = set()
        for _, p in chosen:
            if p in seen:
                continue
            seen.add(p)
            dom = domain_for(p, files)
            text, dtext = tree.read(d, p), tree.read(d, dom) if dom else None
            if text is None or dtext is None:
                continue  # not in this copy of the collection
            os.makedirs(os.path.join(args.dest, d), exist_ok=True)
            with open(os.path.join(args.dest, d, p), "wb") as f:
                f.write(text)
            with open(os.path.join(args.dest, d, dom), "wb") as f:
                f.write(dtext)
            kept += 1
        total += kept
        print("%-28s %d problems" % (d, kept))
    print("%d problems in %d domains" % (total, len(DOMAINS)))


if __name__ == "__main__":
    sys.exit(main())
