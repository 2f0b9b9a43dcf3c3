"""The first example of bindings/python/README.md runs and prints what the README says."""
import os
import re


def test_readme_example(capsys):
    readme = os.path.join(os.path.dirname(__file__), "..", "README.md")
    code = re.search(r"```python\n(.*?)```", open(readme).read(), re.S).group(1)
    exec(compile(code, "README.md", "exec"), {})
    assert capsys.readouterr().out.splitlines() == ["0 []", "1 []", "2 [[0, 1]]", "3 [[0, 1]]"]
