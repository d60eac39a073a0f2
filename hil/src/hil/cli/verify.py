"""`hil verify`: requirement-based suites against the device under test (hil.verify)."""
from __future__ import annotations

import argparse
import dataclasses
import shlex

from hil.cli.common import rig_config
from hil.cli.usage import EXIT_VERIFY_ERROR, UsageError
from hil.io.rundir import staged_run
from hil.verify import fields, report, runner, suite


def _suites(args: argparse.Namespace) -> list[suite.Suite]:
    """The named suites, validated, narrowed to --case."""
    if not args.suites:
        raise UsageError("verify: name at least one suite (hil verify --list shows the shipped ones)")
    try:
        suites = [suite.load(suite.find(name)) for name in args.suites]
    except suite.SuiteError as e:
        raise UsageError(f"verify: {e}") from None
    if not args.case:
        return suites
    unknown = sorted(set(args.case) - {c.id for s in suites for c in s.cases})
    if unknown:
        raise UsageError(f"verify: --case {', '.join(unknown)}: no such case in {', '.join(args.suites)}")
    narrowed = [dataclasses.replace(s, cases=tuple(c for c in s.cases if c.id in args.case)) for s in suites]
    return [s for s in narrowed if s.cases]


def run(args: argparse.Namespace) -> int:
    if args.fields:
        print(fields.describe())
        return 0
    if args.list:
        for name, path in suite.shipped().items():
            s = suite.load(path)
            print(f"{name:<24} {len(s.cases):3d} cases  {len(s.requirements):3d} requirements  {s.title}")
        return 0
    suites = _suites(args)
    out = args.report or args.out
    device = [f"--target={args.target}"] + ([f"--fcc-args={args.fcc_args}"] if args.fcc_args else []) \
        + ([f"--key-file={args.key_file}"] if args.key_file else [])
    command = shlex.join(["hil", "verify", *args.suites, *device])
    with staged_run(out, "verify", force=args.force) as stage:
        base = dataclasses.replace(rig_config(args, stage), progress=False)
        results = runner.run_suites(suites, base, stage, lambda s, c: runner.refly_command(s, c, device),
                                    lambda r: print(report.line(r), flush=True))
        report.html_report(results, suites, stage, args.target, command)
    if args.junit is not None:
        report.junit(results, suites, args.junit, args.target)
    n = report.counts(results)
    print()
    print(report.traceability(results, suites))
    print()
    print(f"verify: {n[runner.PASS]} passed, {n[runner.FAIL]} failed, {n[runner.ERROR]} errors "
          f"(report: {out / 'index.html'})")
    return EXIT_VERIFY_ERROR if n[runner.ERROR] else 1 if n[runner.FAIL] else 0
