"""The README's example runs as written."""

import re
from pathlib import Path

README = Path(__file__).parents[1] / "README.md"


def test_readme_python_example_runs(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "README has no python example"
    monkeypatch.chdir(tmp_path)
    for code in blocks:
        exec(compile(code, str(README), "exec"), {"__name__": "readme"})
    # pillar on ground (0.4 x 0.2 m) and lintel on pillar (0.4 x 0.2 m): hand computed
    assert "2 interfaces, areas [m^2]: [0.08 0.08]" in capsys.readouterr().out
    assert (tmp_path / "scene.vtu").exists() and (tmp_path / "scene.json").exists()
