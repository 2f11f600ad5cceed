"""docs/python.md's worked example runs: its python code blocks, in order, in one namespace, in a
folder of their own that sees the repository's scenes."""
import re

from conftest import ROOT


def test_the_worked_example_runs(tmp_path, monkeypatch):
    page = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, re.S)
    assert len(blocks) >= 3
    (tmp_path / "scenes").symlink_to(ROOT / "scenes")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)
    rows = namespace["rows"]
    assert len(rows) == 12 and all(r["status"] == "ok" for r in rows)
    assert (tmp_path / "python-speed-accuracy.png").stat().st_size > 0
