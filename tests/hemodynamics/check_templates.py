"""The report's templates through the `ibvalve` program (run by CTest with Debian's python3).

usage: check_templates.py IBVALVE LUMPED_CASE SOURCE_DIR

- `ibvalve report --write-templates DIR` writes the built-in report.html.tpl and report.md.tpl, equal to
  hemodynamics/templates/ (they are embedded at build time), and refuses to overwrite them (exit 2);
- a lumped run with `report.templates` = a folder holding a report.html.tpl with a marker writes a
  report.html showing the marker, and the built-in report.md.tpl serves for the file the folder lacks;
- `ibvalve report RUN_DIR` uses the templates the run's config.toml records;
- a broken template is refused with exit 2 and one error line naming the file, by `ibvalve report
  --templates` (the run's report/ is not written) and by `ibvalve run` (no run folder is made).
Prints what it checked; exits 1 on the first failure.
"""
import pathlib
import shutil
import subprocess
import sys


def fail(message, output=""):
    print(output)
    print(f"FAIL: {message}")
    sys.exit(1)


def run(*args):
    p = subprocess.run([str(a) for a in args], stdin=subprocess.DEVNULL, capture_output=True, text=True,
                       timeout=240)
    return p.returncode, p.stdout + p.stderr, p.stderr


def refused(what, naming, *args):
    code, out, err = run(*args)
    errors = [line for line in err.splitlines() if line.startswith("error:")]
    if code != 2 or len(errors) != 1 or naming not in errors[0]:
        fail(f"{what}: exit {code}, expected 2 and one error line naming {naming}", out)
    print(f"ok: {what}: exit 2: {errors[0]}")


def main():
    ibvalve, case, source = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    work = pathlib.Path("templates_work").resolve()
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir()

    mine = work / "mine"
    code, out, _ = run(ibvalve, "report", "--write-templates", mine)
    if code != 0:
        fail(f"--write-templates exited with {code}", out)
    for name in ("report.html.tpl", "report.md.tpl"):
        if (mine / name).read_text() != (source / "hemodynamics" / "templates" / name).read_text():
            fail(f"the written {name} differs from hemodynamics/templates/{name}")
    print("ok: --write-templates wrote the built-in templates, equal to hemodynamics/templates/")
    refused("--write-templates into a folder that has them", "report.html.tpl",
            ibvalve, "report", "--write-templates", mine)

    html = (mine / "report.html.tpl").read_text()
    (mine / "report.html.tpl").write_text(html.replace("<body>\n", "<body>\n<p id=\"marker\">restyled {{run}}</p>\n"))
    (mine / "report.md.tpl").unlink()
    directory = work / "run"
    code, out, _ = run(ibvalve, "run", case, "-o", directory, "--set", "time.cycles=1", "--set",
                       "report.plots=false", "--set", f"report.templates={mine}")
    if code != 0:
        fail(f"the lumped run with report.templates exited with {code}", out)
    report = directory / "report"
    if '<p id="marker">restyled run</p>' not in (report / "report.html").read_text():
        fail("report.html does not show the marker of the user's template", (report / "report.html").read_text())
    if not (report / "report.md").read_text().startswith("# ibvalve report: run, cycle 1 of 1\n\nCycle 1 of 1: ["):
        fail("report.md is not laid out by the built-in template", (report / "report.md").read_text())
    print("ok: the run's report.html shows the user's template; report.md is the built-in one's")

    shutil.rmtree(report)
    code, out, _ = run(ibvalve, "report", directory, "--no-plots")
    if code != 0 or '<p id="marker">' not in (report / "report.html").read_text():
        fail(f"`ibvalve report` (exit {code}) did not use the templates of the run's config.toml", out)
    print("ok: `ibvalve report RUN_DIR` uses the templates its config.toml records")

    broken = work / "broken"
    broken.mkdir()
    (broken / "report.html.tpl").write_text(html.replace("{{/metrics}}\n", ""))
    shutil.rmtree(report)
    refused("a broken report.html.tpl (ibvalve report)", str(broken / "report.html.tpl"),
            ibvalve, "report", directory, "--templates", broken, "--no-plots")
    if report.exists():
        fail("ibvalve report wrote report/ although its template was broken")
    refused("a broken report.html.tpl (ibvalve run)", str(broken / "report.html.tpl"),
            ibvalve, "run", case, "-o", work / "run2", "--set", f"report.templates={broken}")
    if (work / "run2").exists():
        fail("ibvalve run made a run folder although its report template was broken")
    refused("a missing templates folder", "report.templates", ibvalve, "run", case, "-o", work / "run3",
            "--set", f"report.templates={work / 'absent'}")
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
