"""`hil verify`: requirement-based suites against the device under test (hil.verify)."""
from __future__ import annotations

import argparse
import dataclasses
import shlex
import sys
from contextlib import nullcontext
from pathlib import Path

from hil.cli.common import rig_config
from hil.cli.many import parallel_options
from hil.cli.usage import EXIT_VERIFY_ERROR, PROG, UsageError
from hil.io.paths import source_tree, tool
from hil.io.rundir import staged_run
from hil.verify import coverage, fields, report, runner, suite
from hil.verify.platform import INCONCLUSIVE


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
    parallel = _parallel(args, suites)
    cov = _coverage_ready(args) if args.coverage else None
    out = args.report or args.out
    device = [f"--target={args.target}"] + ([f"--fcc-args={args.fcc_args}"] if args.fcc_args else []) \
        + ([f"--key-file={args.key_file}"] if args.key_file else [])
    command = shlex.join(["hil", "verify", *args.suites, *device])
    try:
        with staged_run(out, "verify", force=args.force) as stage:
            base = dataclasses.replace(rig_config(args, stage), progress=False)
            with coverage.profiles_to(stage / "coverage") if cov else nullcontext():  # fcc --check-args too
                results = runner.run_suites(suites, base, stage, lambda s, c: runner.refly_command(s, c, device),
                                            lambda r: print(report.line(r), flush=True), coverage=cov is not None,
                                            parallel=parallel)
            n = report.counts(results)
            matrix = _measure(results, *cov) if cov and not n[runner.ERROR] else None
            report.html_report(results, suites, stage, args.target, command, matrix)
            if matrix is not None:
                report.work_lists(matrix, stage)
            if n[runner.ERROR]:   # kept aside by staged_run: the last report stays as it was
                if args.junit is not None:
                    report.junit(results, suites, stage / "junit.xml", args.target)
                raise Unpublished(f"{n[runner.ERROR]} case(s) could not run: the report is not published")
    except Unpublished as e:
        _summary(results, suites, n, "not published: the previous one is kept")
        print(f"{PROG}: verify: {e}; {out} and --junit are as they were "
              f"({'; '.join(getattr(e, '__notes__', ()))})", file=sys.stderr)
        return EXIT_VERIFY_ERROR
    if args.junit is not None:
        report.junit(results, suites, args.junit, args.target, matrix)
    _summary(results, suites, n, str(out / "index.html"))
    if matrix is not None:
        print(coverage.summary(matrix))
    if n[INCONCLUSIVE]:   # not a failure of the device, never a silent pass: said on stderr too
        print(f"{PROG}: verify: warning: {n[INCONCLUSIVE]} case(s) inconclusive: a timing requirement failed on "
              f"a platform that did not keep its schedule (cyclictest's figures in each line); no verdict on "
              f"the firmware for them", file=sys.stderr)
    return 1 if n[runner.FAIL] else 0


def _parallel(args: argparse.Namespace, suites: list[suite.Suite]) -> dict[str, object] | None:
    """--workers/--scheduler: the flights of cases of `flights = N`, lockstep, spread on rigs of
    their own from the host shell (hil.cli.many.parallel_options); every case must be one."""
    par = parallel_options(args)
    if par is None:
        return None
    single = [c.id for s in suites for c in s.cases if c.n_flights == 1 or c.mode != "lockstep"]
    if single:
        raise UsageError(f"verify: --workers/--scheduler fly the flights of lockstep cases of `flights = N`; "
                         f"{', '.join(single[:3])}{' ...' if len(single) > 3 else ''} fly on this shell's bus: "
                         f"name those cases apart (--case) or fly them without --workers")
    if args.coverage:
        raise UsageError("verify: --coverage measures fcc in this shell's rig: not with --workers/--scheduler")
    return par


def _coverage_ready(args: argparse.Namespace) -> tuple[Path, Path]:
    """--coverage: the coverage-built fcc and the unit tests' coverage (the source tree's
    build-cov, scripts/test coverage), checked before anything flies."""
    tree = source_tree()
    if args.target != "host" or tree is None:
        raise UsageError("verify: --coverage needs --target host and the source tree (its build-cov)")
    fcc, unit_dir = tool("fcc"), tree / "build-cov"
    try:
        coverage.check_ready(fcc, unit_dir)
    except coverage.CoverageError as e:
        raise UsageError(f"verify: --coverage: {e}") from None
    return fcc, unit_dir


def _measure(results: list[runner.CaseResult], fcc: Path, unit_dir: Path) -> coverage.Matrix:
    """The matrix of the cases that ran; evidence that cannot be measured: the run is not published."""
    try:
        return coverage.measure([(r.suite, r.case.requirements, r.run_dir) for r in results if r.run_dir is not None],
                                fcc, unit_dir)
    except coverage.CoverageError as e:
        raise Unpublished(f"coverage: {e}") from None


class Unpublished(Exception):
    """A case could not run: the run's report is kept in OUT.failed-TIME (hil.io.rundir)."""


def _summary(results: list[runner.CaseResult], suites: list[suite.Suite], n: dict[str, int],
             report_at: str) -> None:
    """The traceability matrix and the counts, after the cases' lines."""
    print()
    print(report.traceability(results, suites))
    print()
    print(f"verify: {n[runner.PASS]} passed, {n[runner.FAIL]} failed, "
          f"{n[INCONCLUSIVE]} inconclusive (platform-limited), {n[runner.ERROR]} errors (report: {report_at})")
