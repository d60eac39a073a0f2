"""misra_gate -- judge cppcheck's MISRA C:2012 findings against their recorded counts and deviations.

    python misra_gate.py FINDINGS [--lower | --record] [--summary PAGE]

FINDINGS: cppcheck's output with --template='{file}:{line}:{column}:{id}:{severity}' (scripts/test
misra writes it).  Counts the findings of cppcheck's misra addon per rule and per file, the
hand-written portable firmware apart from the generated bus code (reported, not gated), and
compares the hand-written counts with tests/misra/counts.json: a count above its record, or a rule
or a file that had none, fails; the counts that fell are printed, to be lowered with --lower
(which writes only when nothing rose; --record writes today's counts whatever they are).  A
finding that says the checker could not read a file fails too: a count of nothing proves nothing.  The last line is
`misra: N findings (Required R, Advisory A, Mandatory M); generated G`.

Deviations (MISRA Compliance:2020): every finding of a Required rule, in the hand-written and the
generated code, must be covered by a deviation record of tests/misra/deviations.toml (per rule and
file, the number of findings it covers), which cites the rule's deviation permit there (rationale,
conditions, risk, mitigation); a finding of a Mandatory rule admits none. A finding beyond its
records fails; records that cover more than is found are printed, and --lower / --record rewrite
them with the counts (a new record's reviewer is "pending" until a person signs it).
Advisory rules that are disapplied (the re-categorisation plan in the same file) need no record.
--summary PAGE writes the guideline compliance summary (markdown) of every rule the addon checks.

Exit status 0: no count rose and every Required finding is under a record; 1: a count rose, a
finding is not under a record, or the check was incomplete; 2: a missing or malformed input.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import tomllib
from collections import Counter
from dataclasses import dataclass
from datetime import date
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
COUNTS = ROOT / "tests/misra/counts.json"
DEVIATIONS = ROOT / "tests/misra/deviations.toml"
# Everything below this line of DEVIATIONS is written by --lower / --record.
RECORDS_MARK = "# ---- deviation records: written by `misra_gate.py FINDINGS --lower` (or --record); review the diff"
PERMIT_FIELDS = ("scope", "rationale", "conditions", "risk", "mitigation", "raised_by", "approved_by")
PENDING = "pending"
# cppcheck's addon: its rule functions are the rules it checks (for the summary).
ADDON_GLOB = ".venv-tools/lib/python*/site-packages/cppcheck/data/addons/misra.py"
RULE_PREFIX = "misra-c2012-"
# What tells that cppcheck or its addon did not analyse all of a file.
INCOMPLETE = ("internalError", "syntaxError", "cppcheckError", "internalAstError", "unknownMacro",
              "preprocessorErrorDirective", "misra-config")
# MISRA C:2012 (with Amendments 1-4) rule categories, as its rule table gives them; every rule not
# listed is Required.  Only the category: the rule texts are the licensed document, not shipped.
MANDATORY = {"9.1", "12.5", "13.6", "17.3", "17.4", "17.6", "19.1", "21.13", "21.17", "21.18", "21.19",
             "21.20", "21.22", "22.2", "22.4", "22.5", "22.6"}
ADVISORY = {"1.2", "2.3", "2.4", "2.5", "2.6", "2.7", "4.2", "5.9", "8.7", "8.9", "8.11", "8.13", "10.5",
            "11.4", "11.5", "12.1", "12.3", "12.4", "13.3", "13.4", "15.1", "15.4", "15.5", "17.5", "17.8",
            "18.4", "18.5", "19.2", "20.1", "20.5", "20.10", "21.12"}

Counts = dict[str, dict[str, int]]  # rule -> file -> findings


class InputError(Exception):
    """A missing or malformed input file: exit status 2."""


def category(rule: str) -> str:
    return "Mandatory" if rule in MANDATORY else "Advisory" if rule in ADVISORY else "Required"


def rule_key(rule: str) -> tuple[int, ...]:
    return tuple(int(p) for p in rule.split(".") if p.isdigit())


def firmware_path(path: str) -> str:
    p = Path(path)
    p = (p if p.is_absolute() else ROOT / p).resolve()
    try:
        return str(p.relative_to(ROOT / "firmware"))
    except ValueError:
        return str(p)


def read_findings(path: Path) -> tuple[Counts, Counts, list[str], int]:
    """Hand-written and generated counts, the lines that say the check is incomplete (cppcheck ran
    with --quiet: every line is a finding), cppcheck's own (non-MISRA) findings."""
    try:
        lines = path.read_text().splitlines()
    except OSError as e:
        raise InputError(f"{path}: {e}") from e
    seen: set[tuple[str, ...]] = set()
    counts: dict[bool, Counter[tuple[str, str]]] = {False: Counter(), True: Counter()}
    incomplete, own = [], 0
    for line in lines:
        parts = line.rsplit(":", 4)
        if not line.strip():
            continue
        if len(parts) != 5 or not parts[1].isdigit():  # cppcheck's own error, not a finding
            incomplete.append(line)
            continue
        file, _line, _col, rule_id, _severity = parts
        if rule_id.startswith(INCOMPLETE):
            incomplete.append(line)
            continue
        if not rule_id.startswith(RULE_PREFIX):
            own += 1
            continue
        key = (firmware_path(file), _line, _col, rule_id)
        if key in seen:  # a header's finding, once per file that includes it
            continue
        seen.add(key)
        counts["generated/" in key[0]][(rule_id[len(RULE_PREFIX):], key[0])] += 1
    if not counts[False]:
        incomplete.append(f"{path}: no MISRA finding at all (did the addon run?)")
    return nest(counts[False]), nest(counts[True]), incomplete, own


def nest(flat: Counter[tuple[str, str]]) -> Counts:
    out: Counts = {}
    for (rule, file), n in sorted(flat.items()):
        out.setdefault(rule, {})[file] = n
    return out


def total(counts: Counts) -> int:
    return sum(sum(files.values()) for files in counts.values())


def read_record(path: Path) -> tuple[Counts, Counts]:
    try:
        record = json.loads(path.read_text())
        return record["hand-written"], record["generated"]
    except (OSError, ValueError, KeyError) as e:
        raise InputError(f"{path}: not a MISRA count record ({e})") from e


def write_record(path: Path, hand: Counts, generated: Counts) -> None:
    about = ("MISRA C:2012 findings of cppcheck's misra addon per rule and file (scripts/test misra): "
             "a hand-written count may only fall; lower them with "
             "`python scripts/lib/misra_gate.py build-misra/findings.txt --lower`. "
             "The generated code's counts are recorded, not gated.")
    ordered = {r: hand[r] for r in sorted(hand, key=rule_key)}
    ordered_gen = {r: generated[r] for r in sorted(generated, key=rule_key)}
    path.write_text(json.dumps({"_about": about, "hand-written": ordered, "generated": ordered_gen},
                               indent=1) + "\n")


@dataclass
class Deviations:
    permits: dict[str, dict[str, str]]  # rule -> the permit's fields
    disapplied: dict[str, str]  # Advisory rule -> why it is disapplied
    records: dict[tuple[str, str], tuple[int, str]]  # (rule, file) -> findings covered, reviewer


def read_deviations(path: Path) -> Deviations:
    try:
        data = tomllib.loads(path.read_text())
        permits = {str(r): {k: str(p[k]) for k in PERMIT_FIELDS} for r, p in data.get("permits", {}).items()}
        disapplied = {str(r): str(why) for r, why in data.get("disapplied", {}).items()}
        records = {(str(rule), str(place)): (int(rec["findings"]), str(rec["reviewer"]))
                   for rule, places in data.get("records", {}).items() for place, rec in places.items()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as e:
        raise InputError(f"{path}: not a deviation file ({e})") from e
    for rule in [r for r, _ in records if r not in permits] + [r for r in disapplied if category(r) != "Advisory"]:
        raise InputError(f"{path}: rule {rule}: a record without a permit, or a disapplied rule that is not Advisory")
    return Deviations(permits, disapplied, records)


def merged(hand: Counts, generated: Counts) -> dict[tuple[str, str], int]:
    return {(rule, file): n for counts in (hand, generated) for rule, files in counts.items()
            for file, n in files.items()}


def check_deviations(found: dict[tuple[str, str], int], dev: Deviations) -> tuple[list[str], list[str]]:
    """The findings no record covers (or that admit none), and the records that cover more."""
    missing, over = [], []
    for (rule, file), n in sorted(found.items(), key=lambda kv: (rule_key(kv[0][0]), kv[0][1])):
        covered = dev.records.get((rule, file), (0, ""))[0]
        if category(rule) == "Mandatory":
            missing.append(f"rule {rule} (Mandatory) in {file}: {n} findings; a Mandatory rule admits no deviation")
        elif category(rule) == "Required" and n > covered:
            permit = "" if rule in dev.permits else " and no permit for the rule"
            missing.append(f"rule {rule} (Required) in {file}: {n} findings, {covered} under deviation records{permit}")
    for (rule, file), (covered, _) in sorted(dev.records.items()):
        if covered > found.get((rule, file), 0):
            over.append(f"rule {rule} in {file}: {covered} recorded, {found.get((rule, file), 0)} found")
    return missing, over


def write_records(path: Path, found: dict[tuple[str, str], int], dev: Deviations) -> None:
    """Rewrite the records below RECORDS_MARK: one per Required rule and file with findings."""
    head = path.read_text().split(RECORDS_MARK)[0]
    lines = [RECORDS_MARK]
    rules = sorted({r for r, _ in found if category(r) == "Required"}, key=rule_key)
    for rule in rules:
        lines.append(f'\n[records."{rule}"]')
        for (r, file), n in sorted(found.items()):
            if r == rule:
                reviewer = dev.records.get((rule, file), (0, PENDING))[1]
                lines.append(f'"{file}" = {{ findings = {n}, reviewer = "{reviewer}" }}')
    path.write_text(head + "\n".join(lines) + "\n")


def addon_rules() -> list[str]:
    """The rules cppcheck's misra addon checks (its misra_X_Y functions)."""
    for addon in ROOT.glob(ADDON_GLOB):
        return sorted({f"{a}.{b}" for a, b in re.findall(r"def misra_(\d+)_(\d+)\(", addon.read_text())},
                      key=rule_key)
    raise InputError(f"no cppcheck misra addon at {ADDON_GLOB} (scripts/setup installs it)")


def write_summary(path: Path, hand: Counts, generated: Counts, dev: Deviations) -> None:
    """MISRA Compliance:2020's guideline compliance summary: a page, one row per rule."""
    rows = ["| rule | category | compliance | hand-written | generated |", "|---|---|---|---:|---:|"]
    tally: Counter[tuple[str, str]] = Counter()
    for rule in sorted(set(addon_rules()) | set(hand) | set(generated), key=rule_key):
        n_hand, n_gen = sum(hand.get(rule, {}).values()), sum(generated.get(rule, {}).values())
        cat = category(rule)
        if n_hand + n_gen == 0:
            status = "Compliant"
        elif cat == "Required":
            status = "Deviations"
        elif cat == "Advisory" and rule in dev.disapplied:
            status = "Disapplied"
        else:
            status = "Violations"
        tally[(cat, status)] += 1
        rows.append(f"| {rule} | {cat} | {status} | {n_hand} | {n_gen} |")
    summary = ["| category | " + " | ".join(STATUSES) + " |", "|---|" + "---:|" * len(STATUSES)]
    for cat in ("Mandatory", "Required", "Advisory"):
        summary.append(f"| {cat} | " + " | ".join(str(tally[(cat, s)]) for s in STATUSES) + " |")
    path.write_text(SUMMARY_HEAD.format(day=date.today()) + "\n".join(summary) + "\n\n" + "\n".join(rows) + "\n")


STATUSES = ("Compliant", "Deviations", "Disapplied", "Violations")
SUMMARY_HEAD = """# MISRA C:2012 guideline compliance summary

<!-- written by `python scripts/lib/misra_gate.py build-misra/findings.txt --summary docs/misra-compliance.md`
     after `scripts/test misra`; do not edit by hand -->

The guideline compliance summary of MISRA Compliance:2020 for the portable firmware and its
generated bus code, from `scripts/test misra` on {day}: every rule that cppcheck 2.22's misra
addon checks, its category, and its compliance. **Compliant**: no finding. **Deviations**: the
findings of a Required rule, each covered by a deviation record that cites the rule's deviation
permit (`tests/misra/deviations.toml`: rationale, conditions, risk, mitigation, sign-off); the
step fails on a Required finding without a record and on any Mandatory finding. **Disapplied**:
an Advisory rule that the re-categorisation plan in the same file disapplies, with its reason
(the findings are still counted and may only fall: `tests/misra/counts.json`). Rules the addon
does not check (most of the directives, and rules it cannot decide) are not listed and not
claimed; how the step works: [Certification evidence](certification.md).

"""


def compare(now: Counts, record: Counts) -> tuple[list[str], list[str]]:
    """The counts that rose (or are new) and those that fell."""
    rose, fell = [], []
    for rule in sorted(set(now) | set(record), key=rule_key):
        files_now, files_then = now.get(rule, {}), record.get(rule, {})
        for file in sorted(set(files_now) | set(files_then)):
            n, was = files_now.get(file, 0), files_then.get(file, 0)
            if n > was:
                rose.append(f"rule {rule} ({category(rule)}) in {file}: {n} findings, recorded {was}")
            elif n < was:
                fell.append(f"rule {rule} in {file}: {was} -> {n}")
    return rose, fell


def print_rules(hand: Counts, generated: Counts) -> None:
    print(f"{'rule':8} {'category':10} {'hand-written':>12} {'generated':>10}  most in")
    for rule in sorted(set(hand) | set(generated), key=rule_key):
        files = hand.get(rule, {})
        worst = max(files, key=lambda f: files[f]) if files else "-"
        print(f"{rule:8} {category(rule):10} {sum(files.values()):12} "
              f"{sum(generated.get(rule, {}).values()):10}  {worst}")


def by_category(counts: Counts) -> Counter[str]:
    cats: Counter[str] = Counter()
    for rule, files in counts.items():
        cats[category(rule)] += sum(files.values())
    return cats


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("findings", type=Path)
    parser.add_argument("--lower", action="store_true", help="write the counts that fell")
    parser.add_argument("--record", action="store_true",
                        help="write today's counts as the record, risen ones too (review the diff)")
    parser.add_argument("--summary", type=Path, help="write the guideline compliance summary (markdown) here")
    args = parser.parse_args()
    try:
        hand, generated, incomplete, own = read_findings(args.findings)
        found = merged(hand, generated)
        if args.record and not incomplete:
            write_record(COUNTS, hand, generated)
            write_records(DEVIATIONS, found, read_deviations(DEVIATIONS))
        record_hand, _ = read_record(COUNTS)
        dev = read_deviations(DEVIATIONS)
        if args.summary:
            write_summary(args.summary, hand, generated, dev)
    except InputError as e:
        print(f"misra_gate: {e}", file=sys.stderr)
        return 2
    print_rules(hand, generated)
    print(f"cppcheck's own findings (not MISRA, not gated): {own}")
    rose, fell = compare(hand, record_hand)
    for line in incomplete:
        print(f"misra: incomplete check: {line}")
    for line in rose:
        print(f"misra: rose: {line}")
    if fell and args.lower and not rose and not incomplete:
        write_record(COUNTS, hand, generated)
        print(f"misra: {len(fell)} counts lowered in {COUNTS.relative_to(ROOT)}")
    else:
        for line in fell:
            print(f"misra: fell (lower with --lower): {line}")
    missing, over = check_deviations(found, dev)
    for line in missing:
        print(f"misra: no deviation: {line}")
    if over and args.lower and not missing and not incomplete:
        write_records(DEVIATIONS, found, dev)
        print(f"misra: {len(over)} deviation records lowered in {DEVIATIONS.relative_to(ROOT)}")
    else:
        for line in over:
            print(f"misra: deviation record covers more than is found (lower with --lower): {line}")
    required = sum(n for (rule, _), n in found.items() if category(rule) == "Required")
    pending = sum(1 for _, reviewer in dev.records.values() if reviewer == PENDING)
    print(f"misra: deviations: {required} Required findings under {len(dev.records)} records of "
          f"{len(dev.permits)} permits ({pending} records awaiting a reviewer); "
          f"{len(dev.disapplied)} Advisory rules disapplied")
    cats = by_category(hand)
    print(f"misra: {total(hand)} findings (Required {cats['Required']}, Advisory {cats['Advisory']}, "
          f"Mandatory {cats['Mandatory']}); generated {total(generated)}")
    return 1 if rose or incomplete or missing else 0


if __name__ == "__main__":
    sys.exit(main())
