"""misra_gate -- judge cppcheck's MISRA C:2012 findings against their recorded counts.

    python misra_gate.py FINDINGS [--lower]

FINDINGS: cppcheck's output with --template='{file}:{line}:{column}:{id}:{severity}' (scripts/test
misra writes it).  Counts the findings of cppcheck's misra addon per rule and per file, the
hand-written portable firmware apart from the generated bus code (reported, not gated), and
compares the hand-written counts with tests/misra/counts.json: a count above its record, or a rule
or a file that had none, fails; the counts that fell are printed, to be lowered with --lower
(which writes only when nothing rose; --record writes today's counts whatever they are).  A
finding that says the checker could not read a file fails too: a count of nothing proves nothing.  The last line is
`misra: N findings (Required R, Advisory A, Mandatory M); generated G`.
Exit status 0: no count rose; 1: a count rose or the check was incomplete; 2: a missing or
malformed input.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
COUNTS = ROOT / "tests/misra/counts.json"
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
    args = parser.parse_args()
    try:
        hand, generated, incomplete, own = read_findings(args.findings)
        if args.record and not incomplete:
            write_record(COUNTS, hand, generated)
        record_hand, _ = read_record(COUNTS)
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
    cats = by_category(hand)
    print(f"misra: {total(hand)} findings (Required {cats['Required']}, Advisory {cats['Advisory']}, "
          f"Mandatory {cats['Mandatory']}); generated {total(generated)}")
    return 1 if rose or incomplete else 0


if __name__ == "__main__":
    sys.exit(main())
