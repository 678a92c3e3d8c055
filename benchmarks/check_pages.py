"""The built book's pages as a reader's browser lays them out: tables and figures against the text column.

Run: python benchmarks/check_pages.py [--pages 'decay*'] [--width 1280] [--shots DIR]

Opens each page of ``_build/html/book`` (build the book first) in headless Chromium (the
``chromium`` binary; ``apt-get install chromium``), driven over the DevTools protocol with the
websocket client of tornado (installed with the book's requirements), at a window ``--width``
pixels wide. For each page it prints the article's text column (px) and:

- every table whose right edge runs past the column without a scrolling box (``clipped``), and
  every table that scrolls inside its box (``scrolls``, with its width and the box's): these show
  the edge shadow of ``book/_static/semitrack.css``;
- every figure past the column (``clipped``) and the narrowest figure's shown width (px): a figure
  drawn with :func:`semitrack.plotting.style.legible_text` has text of at least 10 px times its
  shown width over 690.

``--shots DIR`` also saves a full-page screenshot of each page (their layout can sit some 100 px
left of a plain ``chromium --screenshot``'s: judge the measurements, not the picture's margins).
Nothing is asserted: the findings go into the notes.
"""

from __future__ import annotations

import argparse
import asyncio
import base64
import json
import subprocess
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PORT = 9333

#: Measures the page in the browser: the column, each table (its box, whether a box scrolls it) and figure.
LAYOUT = r"""
(() => {
  const article = document.querySelector('article.bd-article') || document.querySelector('main') || document.body;
  const col = article.getBoundingClientRect();
  const out = {column: [Math.round(col.left), Math.round(col.right)], clipped: [], scrolls: [], figures: []};
  const scroller = el => {
    for (let a = el; a; a = a.parentElement) {
      if (['auto', 'scroll'].includes(getComputedStyle(a).overflowX)) return a;
    }
    return null;
  };
  document.querySelectorAll('article table').forEach((t, i) => {
    const r = t.getBoundingClientRect(), box = scroller(t);
    if (!box && r.right > col.right + 2) out.clipped.push(`table ${i}: right edge ${Math.round(r.right)} px`);
    else if (box && box.scrollWidth > box.clientWidth + 1)
      out.scrolls.push(`table ${i}: ${box.scrollWidth} in ${box.clientWidth} px`);
  });
  document.querySelectorAll('article img').forEach((im, i) => {
    const r = im.getBoundingClientRect();
    if (im.naturalWidth > 200) out.figures.push(Math.round(r.width));
    if (r.right > col.right + 2) out.clipped.push(`figure ${i}: right edge ${Math.round(r.right)} px`);
  });
  out.height = document.documentElement.scrollHeight;
  return JSON.stringify(out);
})()
"""


async def _check(pages: list[Path], width: int, shots: Path | None, url: str) -> None:
    from tornado.websocket import websocket_connect

    ws = await websocket_connect(url, max_message_size=1 << 30)
    counter = 0

    async def call(method: str, **params):
        nonlocal counter
        counter += 1
        await ws.write_message(json.dumps({"id": counter, "method": method, "params": params}))
        while True:
            message = json.loads(await ws.read_message())
            if message.get("id") == counter:
                return message.get("result", message)

    await call("Page.enable")
    await call("Emulation.setDeviceMetricsOverride", width=width, height=1000, deviceScaleFactor=1, mobile=False)
    for page in pages:
        await call("Page.navigate", url=page.as_uri())
        await asyncio.sleep(2.0)  # MathJax and the theme's scripts lay the page out after the load
        found = json.loads((await call("Runtime.evaluate", expression=LAYOUT, returnByValue=True))["result"]["value"])
        narrowest = min(found["figures"]) if found["figures"] else "-"
        print(f"{page.stem:14s} column {found['column']}, {len(found['figures'])} figures (narrowest {narrowest} px); "
              f"clipped: {found['clipped'] or 'none'}; scrolling: {found['scrolls'] or 'none'}")
        if shots is not None:
            shot = await call("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                              clip={"x": 0, "y": 0, "width": width, "height": min(found["height"], 16000), "scale": 1})
            (shots / f"{page.stem}.png").write_bytes(base64.b64decode(shot["data"]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pages", default="*", help="a glob of page names in _build/html/book (default: all)")
    parser.add_argument("--width", type=int, default=1280, help="the browser window's width (px)")
    parser.add_argument("--shots", type=Path, help="a folder for full-page screenshots")
    args = parser.parse_args()
    pages = sorted((ROOT / "_build" / "html" / "book").glob(f"{args.pages}.html"))
    if not pages:
        raise SystemExit("no built pages: build the book first (jupyter-book build . --all)")
    if args.shots is not None:
        args.shots.mkdir(parents=True, exist_ok=True)
    browser = subprocess.Popen(["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                                f"--remote-debugging-port={PORT}", f"--window-size={args.width},1000", "about:blank"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            try:
                targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{PORT}/json"))
                break
            except OSError:
                time.sleep(0.2)
        else:
            raise SystemExit("chromium did not open its DevTools port")
        url = next(t["webSocketDebuggerUrl"] for t in targets if t["type"] == "page")
        asyncio.run(_check(pages, args.width, args.shots, url))
    finally:
        browser.terminate()


if __name__ == "__main__":
    main()
