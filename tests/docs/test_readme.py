"""The README's Python example runs as written."""

import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_python_blocks_run(capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks
    for code in blocks:
        namespace: dict = {}
        exec(compile(code, str(README), "exec"), namespace)
    out = capsys.readouterr().out
    assert "dp_La/dt" in out
    # the comment under print(G.expr) is what it prints: omega/V of the DC motor by hand,
    # (La s + Ra)(J s + b) + K^2 in the denominator
    assert "K/(J*La*s**2 + K**2 + Ra*b + s*(J*Ra + La*b))" in out
    assert "print(G.expr)                # K/(J*La*s**2 + K**2 + Ra*b + s*(J*Ra + La*b))" in \
        README.read_text()
