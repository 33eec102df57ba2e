#!/usr/bin/python3
"""From a batch to a paper, on a lab folder the independent simulator made
(../shared/tools/vtrib.py, --grow 15, a seed per specimen): two species x
two planes x two directions x three replicates, named as a lab names them
(Buche_RT-R_probe01_reibung.csv with ..._oberflaeche.csv) and in the
paper's style (B-RT-R_rep1_force.csv with B-RT-R_rep1_scan.csv).

- every file pairs without a name pattern, in both namings, and the factor
  columns (species, plane, direction) fill;
- the group table's means are the means of the specimens' mu to quote, its
  intervals their spread's (Student's t); the species differ, the planes
  and directions do not (the simulator's mu differs by species only);
- one specimen re-run with another spring into the audit folder changes
  its row and the groups, and no other specimen's file.

Exit status 1 when a line fails, 77 (skipped) without ../shared/tools.
"""
import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile

CASES = [("B", "RT", "R"), ("B", "RT", "T"), ("B", "RL", "R"), ("B", "RL", "L"),
         ("S", "RT", "R"), ("S", "RT", "T"), ("S", "RL", "R"), ("S", "RL", "L")]
WORD = {"B": "Buche", "S": "Fichte"}
SPECIES = {"B": "beech", "S": "spruce"}
# Student's t, two-sided 95%, for 11 degrees of freedom (12 specimens a
# species), from the tables.
T975_11 = 2.200985

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def make_lab(vtrib, cache):
    """The simulated tests (made once, kept in the cache), linked under the
    two namings."""
    lab, paper = os.path.join(cache, "lab"), os.path.join(cache, "paper")
    if os.path.exists(os.path.join(cache, "done")):
        return lab, paper
    shutil.rmtree(cache, ignore_errors=True)
    for folder in (lab, paper, os.path.join(cache, "truth")):
        os.makedirs(folder)
    seed = 100
    for sp, plane, direction in CASES:
        case = "{}-{}-{}".format(sp, plane, direction)
        for rep in (1, 2, 3):
            seed += 1
            tmp = os.path.join(cache, "tmp")
            subprocess.run([sys.executable, vtrib, "--case", case, "--seed",
                            str(seed), "--grow", "15", "--out", tmp],
                           check=True, capture_output=True)
            force = os.path.join(tmp, case + "_force.csv")
            height = os.path.join(tmp, case + "_Height.csv")
            name = "{}_{}-{}_probe0{}".format(WORD[sp], plane, direction, rep)
            os.link(force, os.path.join(lab, name + "_reibung.csv"))
            os.link(height, os.path.join(lab, name + "_oberflaeche.csv"))
            short = "{}_rep{}".format(case, rep)
            os.link(force, os.path.join(paper, short + "_force.csv"))
            os.link(height, os.path.join(paper, short + "_scan.csv"))
            shutil.move(os.path.join(tmp, case + "_truth.json"),
                        os.path.join(cache, "truth", name + ".json"))
            shutil.rmtree(tmp)
    open(os.path.join(cache, "done"), "w").close()
    return lab, paper


def audit(binary, folder, out, *extra):
    r = subprocess.run([binary, "audit", folder, "-o", out, "--no-figures",
                        "-q"] + list(extra), capture_output=True, text=True)
    return r


def files_under(folder):
    digests = {}
    for root, _, names in os.walk(folder):
        for n in names:
            path = os.path.join(root, n)
            with open(path, "rb") as f:
                digests[os.path.relpath(path, folder)] = hashlib.sha256(
                    f.read()).hexdigest()
    return digests


def level(groups, quantity, factor, name):
    for g in groups:
        if g["quantity"] != quantity:
            continue
        for lv in g["levels"]:
            if lv["factor"] == factor and lv["level"] == name:
                return lv
    return None


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser()
    p.add_argument("--binary", required=True)
    p.add_argument("--cache", default=None,
                   help="where the lab folder is kept (default: "
                        "$XDG_CACHE_HOME/wearscar-worlds, by the simulator's "
                        "hash); the audits go to a temporary folder")
    p.add_argument("--shared", default=os.path.join(here, "..", "..", "..",
                                                    "shared"))
    a = p.parse_args()
    vtrib = os.path.join(a.shared, "tools", "vtrib.py")
    if not os.path.exists(vtrib):
        print("skipped: {} is absent (the independent simulator lives in "
              "../shared/tools)".format(vtrib))
        return 77
    digest = hashlib.sha256(open(vtrib, "rb").read()).hexdigest()[:16]
    if a.cache is None:
        root = os.environ.get("XDG_CACHE_HOME") or os.path.join(
            os.path.expanduser("~"), ".cache")
        a.cache = os.path.join(root, "wearscar-worlds", "lab_batch-" + digest)
    lab, paper = make_lab(vtrib, a.cache)
    work = tempfile.mkdtemp(prefix="wearscar-lab-batch-")
    try:
        return judge(a, lab, paper, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def judge(a, lab, paper, work):
    results = naming(a, lab, paper, work)
    out, rows = results["lab"]
    groups = json.load(open(os.path.join(out, "groups.json")))
    compare(groups, rows)
    exports(a, lab, out, groups, work)
    rerun(a, lab, out, work)
    print("{} of the lines failed".format(len(failures)) if failures
          else "every line holds")
    return 1 if failures else 0


def naming(a, lab, paper, work):
    """Both namings pair every specimen and fill its factors."""
    results = {}
    for style, folder in (("lab", lab), ("paper", paper)):
        out = os.path.join(work, "audit-" + style)
        shutil.rmtree(out, ignore_errors=True)
        r = audit(a.binary, folder, out)
        check(r.returncode == 0, "{} naming: the audit ends with 0 ({})".format(
            style, r.stderr.strip()[-200:]))
        rows = json.load(open(os.path.join(out, "summary.json")))
        results[style] = (out, rows)
        check(len(rows) == 24 and all(row.get("pairing") == "force + scan"
                                      for row in rows),
              "{} naming: 24 specimens, each force file with its scan "
              "({})".format(style, sorted(row.get("pairing") for row in rows)[:2]))
        factors = {(row["species"], row["plane"], row["direction"])
                   for row in rows}
        want = {(SPECIES[s], pl, d) for s, pl, d in CASES}
        check(factors == want, "{} naming: species, plane and direction "
              "filled from the names ({})".format(style, sorted(factors)[:2]))
    return results


def compare(groups, rows):
    """The species' means and intervals, their difference, the plan."""
    mu = [g for g in groups if g["quantity"] == "mu_to_quote"][0]
    for code, species in SPECIES.items():
        values = [row["quote"]["mu"] for row in rows
                  if row["species"] == species]
        lv = level(groups, "mu_to_quote", "species", species)
        mean = sum(values) / len(values)
        sd = (sum((v - mean) ** 2 for v in values) / (len(values) - 1)) ** 0.5
        half = T975_11 * sd / len(values) ** 0.5
        check(lv is not None and lv["specimens"] == 12 and
              abs(lv["mean"] - mean) < 1e-12 and
              abs(lv["interval95"][1] - lv["interval95"][0] - 2 * half) <
              1e-6 * half,
              "{}: the mean of its 12 specimens' mu to quote ({:.5f}) and "
              "the interval from their spread (+-{:.5f})".format(
                  species, mean, half))
    by = {(d["factor"], d["level_a"], d["level_b"]): d
          for d in mu["differences"]}
    species_d = by.get(("species", "beech", "spruce"))
    check(species_d is not None and species_d["different"],
          "the species differ: {}".format(species_d))
    others = [d for d in mu["differences"] if d["factor"] != "species"]
    check(others and not any(d["different"] for d in others),
          "the planes and directions do not: {}".format(
              ["{} {}-{} p={:.2f}".format(d["factor"], d["level_a"],
                                          d["level_b"], d["p"])
               for d in others]))
    check(mu["plan"]["replicates_per_group"] >= 2,
          "the next batch planned: " + mu["plan"]["said"])


def exports(a, lab, out, groups, work):
    """methods.md, a German Excel's CSV, a common window of cycles."""
    methods = open(os.path.join(out, "methods.md")).read()
    check("S = 10.19 N/mm" in methods and
          "24 of 24 specimens gave a mu to quote" in methods and
          "Groups (species, plane, direction)" in methods and
          "@article{zheng_wear_scar,\n  author = {Zheng, Yi and Cabboi, "
          "Alessandro and {van de Kuilen}, Jan-Willem}" in open(os.path.join(
              out, "references.bib")).read(),
          "methods.md says the spring, the specimens quoted and the groups")
    # A German Excel's CSV: semicolons, decimal commas, the same numbers.
    de = os.path.join(work, "audit-de")
    shutil.rmtree(de, ignore_errors=True)
    audit(a.binary, lab, de, "--csv-locale", "de")
    line = [l for l in open(os.path.join(de, "groups.csv")).read().splitlines()
            if l.startswith("mu_to_quote;species;beech;")]
    beech = level(groups, "mu_to_quote", "species", "beech")
    check(line and abs(float(line[0].split(";")[4].replace(",", ".")) -
                       beech["mean"]) < 1e-5,
          "--csv-locale de: {}".format(line[:1]))
    # A common window of cycles for every specimen, when asked.
    common = os.path.join(work, "audit-common")
    audit(a.binary, lab, common, "--compare-first", "20", "--compare-last",
          "39")
    windows = {(row["comparison"]["first_cycle"], row["comparison"]["last_cycle"])
               for row in json.load(open(os.path.join(common, "summary.json")))}
    check(windows == {(20, 39)}, "--compare-first 20 --compare-last 39: "
          "cycles 20-39 for every specimen ({})".format(sorted(windows)))


def rerun(a, lab, out, work):
    """One specimen again, another spring: only its files and the batch's
    change."""
    # One specimen again, another spring, into the same folder.
    before = files_under(out)
    one = os.path.join(work, "one")
    shutil.rmtree(one, ignore_errors=True)
    os.makedirs(one)
    name = "Buche_RT-R_probe02"
    for suffix in ("_reibung.csv", "_oberflaeche.csv"):
        shutil.copy(os.path.join(lab, name + suffix), one)
    r = audit(a.binary, one, out, "--spring", "14")
    check(r.returncode == 0, "the re-run of one specimen ends with 0")
    after = files_under(out)
    changed = sorted(k for k in before
                     if after.get(k) != before[k] and
                     not k.startswith(name + "/"))
    batch = {"summary.csv", "summary.json", "summary.jsonl", "groups.csv",
             "groups.json", "groups.tex", "group_differences.csv",
             "report.html", ".wearscar-manifest", "parts/audit.json",
             "summary.xlsx", "groups.xlsx", "methods.md", "references.bib"}
    check(all(k in batch for k in changed),
          "no other specimen's file changed (changed: {})".format(changed))
    check(after.get(name + "/result.json") != before.get(name + "/result.json")
          and "groups.json" in changed,
          "its result and the groups changed")
    rows2 = json.load(open(os.path.join(out, "summary.json")))
    check(len(rows2) == 24, "the batch still holds 24 specimens")


if __name__ == "__main__":
    sys.exit(main())
