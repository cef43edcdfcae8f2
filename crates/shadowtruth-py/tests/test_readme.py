"""The README's Python example runs as written and prints what the command counts: with every
pixel drawn lit, the false-lit pixels are the pixels the command's reference mask shadows."""

import contextlib
import io
import os
import re

import numpy as np
from PIL import Image

from conftest import WORKSPACE


def readme_python_example():
    text = (WORKSPACE / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1, "the README has one Python example"
    return blocks[0]


def test_the_readme_example_prints_the_commands_shadowed_pixels(command, tmp_path):
    printed = io.StringIO()
    cwd = os.getcwd()
    os.chdir(WORKSPACE)
    try:
        with contextlib.redirect_stdout(printed):
            exec(compile(readme_python_example(), "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    mask_png = tmp_path / "mask.png"
    command("reference", "scenes/plane_box.json", "-o", mask_png)
    shadowed = int(np.count_nonzero(np.asarray(Image.open(mask_png)) == 0))
    assert printed.getvalue().split() == [str(shadowed)]
    assert f"# {shadowed}: every shadowed pixel" in readme_python_example()
