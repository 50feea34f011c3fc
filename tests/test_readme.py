"""The README's examples run as written."""

import re
import subprocess
import sys
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


def test_readme_sweep_example_runs_as_a_script(tmp_path):
    """The sweep example pasted into a file and run with ``python``: its local workers import
    the script again, which only the ``__main__`` guard keeps from starting sweeps of their
    own. 100 tasks, so the store must hold 100 records."""
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    sweep = [b for b in blocks if "run_sweep(" in b]
    assert len(sweep) == 1, "README has one sweep example"
    script = tmp_path / "sweep.py"
    script.write_text(sweep[0])
    proc = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip() == "100 runs, 100 records"
