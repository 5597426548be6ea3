"""``bsi-lfe report --quick``: one HTML + Markdown report per mission objective and an index."""

import re
import xml.etree.ElementTree as ET

import pytest

pytest.importorskip("lfe.dataset")

from lfe import PROPOSITION_DESCRIPTIONS, proposition_roles  # noqa: E402
from lfe.report import OBJECTIVE_TITLES  # noqa: E402

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _run_cli(argv):
    try:
        from lfe.cli import main
    except ImportError:  # the command line is wired by lfe/cli/__init__.py; else the module
        import argparse

        from lfe import report

        parser = argparse.ArgumentParser(prog="bsi-lfe report")
        report.add_arguments(parser)
        return report.run(parser.parse_args(argv[1:]))
    return main(argv)


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("lfe_report")
    status = _run_cli(["report", "--out", str(out), "--quick"])
    return out, status


def test_quick_report_writes_every_objective(quick_run, capsys):
    out, status = quick_run
    assert status in (0, None)
    index = out / "index.html"
    root = ET.fromstring(index.read_text(encoding="utf-8").split("\n", 1)[1])
    links = [a.get("href") for a in root.iter("a")]
    for mo in ("MO1", "MO2", "MO3"):
        assert f"{mo}/report.html" in links and f"{mo}/report.md" in links
        html_text = (out / mo / "report.html").read_text(encoding="utf-8")
        report_root = ET.fromstring(html_text.split("\n", 1)[1])
        text = " ".join("".join(report_root.itertext()).split())
        assert f"{mo}: {OBJECTIVE_TITLES[mo]}" in text
        md = (out / mo / "report.md").read_text(encoding="utf-8")
        assert md.startswith(f"# {mo}: ")
        # every MAP clause appears, in LTL and as a sentence in the commander's words
        # the readable MAP first: "shown clauses  [untested: the others]"
        readable = re.search(r"```text\n(.*)\n```", md).group(1)
        shown, _, untested = readable.partition("  [untested: ")
        clauses = [] if shown == "true" else shown.split(" & ")
        clauses += untested.removesuffix("]").split(" & ") if untested else []
        for clause in clauses:
            assert clause in text
        for png in re.findall(r"\]\(([^)]+\.png)\)", md):
            data = (out / mo / png).read_bytes()
            assert data[:8] == PNG_SIGNATURE and len(data) > 2048
        assert (out / mo / "satisfaction.png").exists()
        assert (out / mo / "confusion_matrix.png").exists()


def test_reports_use_commander_descriptions(quick_run):
    out, _ = quick_run
    roles = proposition_roles()
    md = "\n".join((out / mo / "report.md").read_text(encoding="utf-8")
                   for mo in ("MO1", "MO2", "MO3"))
    # the propositions table describes every proposition of the paper's set
    for name in roles["global_candidates"] + roles["subtasks"]:
        assert PROPOSITION_DESCRIPTIONS[name] in md
    # sentences follow the report's phrasing scheme with those descriptions
    sentences = re.findall(r"^- (Always, .*?\.|Eventually, .*?\.) `", md, flags=re.M)
    assert sentences
    described = set(PROPOSITION_DESCRIPTIONS.values())
    for s in sentences:
        body = s.split(", ", 1)[1][:-1]
        assert body in described


def test_unknown_objective(tmp_path):
    from lfe import make_lfe_dataset
    from lfe.report import explain_objectives

    ds = make_lfe_dataset(n_scenarios=2, random_state=0)
    with pytest.raises(ValueError, match="unknown objective 'MO9'"):
        explain_objectives(ds, objectives=["MO9"])
