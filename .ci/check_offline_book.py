"""Check that the built book renders its equations offline.

Every HTML page under _build/html that holds math must load MathJax from a file of the build
itself (no network), and no page may load MathJax from anywhere else. Exits 1 with the offending
pages listed.
"""

import re
import sys
from pathlib import Path
from urllib.parse import urlsplit

HTML = Path(sys.argv[1] if len(sys.argv) > 1 else "_build/html")
SCRIPT_SRC = re.compile(r"<script\b[^>]*\bsrc=\"([^\"]+)\"", re.IGNORECASE)
MATH = re.compile(r"class=\"[^\"]*\bmath\b", re.IGNORECASE)

problems, with_math = [], 0
for page in sorted(HTML.rglob("*.html")):
    text = page.read_text(encoding="utf-8")
    mathjax = [src for src in SCRIPT_SRC.findall(text) if "mathjax" in src.lower()]
    local = []
    for src in mathjax:
        parts = urlsplit(src)
        target = (page.parent / parts.path).resolve()
        if parts.scheme or parts.netloc or not target.is_file():
            problems.append(f"{page.relative_to(HTML)}: MathJax from {src!r} is not a file of the build")
        else:
            local.append(src)
    if MATH.search(text):
        with_math += 1
        if not local:
            problems.append(f"{page.relative_to(HTML)}: has math but loads no local MathJax")
if problems:
    sys.exit("the book would not render its equations offline:\n  " + "\n  ".join(problems))
if not with_math:
    sys.exit(f"no page under {HTML} holds math: is this the built book?")
print(f"MathJax is local on all {with_math} pages with math")
