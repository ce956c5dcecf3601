"""graphviz's ``dot`` turns DOT text into PNG/SVG (Debian's graphviz package)."""
import os
import shutil
import subprocess

from rqt_graph.errors import GraphError

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf", ".dot": None, ".gv": None}


def render_bytes(dot_text, fmt, timeout=60):
    exe = shutil.which("dot")
    if exe is None:
        raise GraphError("graphviz's 'dot' is not installed: apt-get install graphviz "
                         "(make setup installs it)")
    proc = subprocess.run([exe, "-T" + fmt], input=dot_text.encode(), capture_output=True, timeout=timeout)
    if proc.returncode != 0:
        raise GraphError("dot -T%s failed: %s" % (fmt, proc.stderr.decode(errors="replace").strip()))
    return proc.stdout


def write(dot_text, path):
    """Write the graph to ``path``; the extension picks the format (.png .svg .pdf .dot)."""
    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise GraphError("cannot write '%s': the name must end in one of %s"
                         % (path, " ".join(sorted(FORMATS))))
    data = dot_text.encode() if FORMATS[ext] is None else render_bytes(dot_text, FORMATS[ext])
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
        with open(path, "wb") as f:
            f.write(data)
    except OSError as err:
        raise GraphError("cannot write %s: %s" % (path, err))
    return path
