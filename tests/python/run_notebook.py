"""Executes a notebook as Jupyter would (nbclient, Debian's python3-nbclient, with the python3 kernel
of python3-ipykernel), fails on any cell's error, and writes the executed notebook and its pictures
next to it in the work directory to be looked at.

    run_notebook.py NOTEBOOK WORKDIR     (the sluice module's directory on PYTHONPATH)
"""
import base64
import os
import pathlib
import sys

import nbformat
from nbclient import NotebookClient

# The kernel shows figures inline (matplotlib's own backend there), quietly.
os.environ.pop("MPLBACKEND", None)
os.environ["PYDEVD_DISABLE_FILE_VALIDATION"] = "1"
notebook, workdir = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
workdir.mkdir(parents=True, exist_ok=True)
nb = nbformat.read(notebook, as_version=4)
NotebookClient(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(notebook.parent)}}).execute()
nbformat.write(nb, workdir / notebook.name)
pictures = 0
for k, cell in enumerate(nb.cells):
    for output in cell.get("outputs", []):
        png = output.get("data", {}).get("image/png")
        if png:
            pictures += 1
            (workdir / f"{notebook.stem}_cell{k}_{pictures}.png").write_bytes(base64.b64decode(png))
print(f"{notebook.name}: {len(nb.cells)} cells ran; {pictures} pictures in {workdir}")
if pictures < 3:
    sys.exit(f"{notebook.name}: expected 3 pictures (the front plot and two frames), got {pictures}")
