"""A viewer opened in headless Chromium with the network blocked: its screenshot, console and DOM.

For the tests and the viewer benchmark, and for drawing the README's screenshot: what a person
sees opening the page from disk, offline. Needs Debian's ``chromium`` (``make test`` installs it).
"""

import json
import re
import shutil
import subprocess

from beeoptics.io.errors import InputError

#: The window the viewers are laid out for, pixels.
WINDOW = (1300, 1000)
#: The page's own line, once drawn (beeoptics.images.viewer).
DRAWN = re.compile(r"beeoptics viewer: (\{.*?\})\"")


def chromium():
    """The Chromium executable, or an InputError saying how to install it."""
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    if found is None:
        raise InputError("chromium", "", "not installed (apt-get install chromium; make test installs it)")
    return found


def open_page(page, screenshot=None, fragment="", dom=False, timeout_s=120, virtual_time=True):
    """Open ``page`` (an HTML file) as a browser would from disk, every host name unresolvable.

    Parameters
    ----------
    page : path
    screenshot : path, optional
        Where to write a PNG of the window (:data:`WINDOW`).
    fragment : str
        Appended to the page's URL (``"#receptor=12"``).
    dom : bool
        Also return the DOM once the page's scripts have run.
    virtual_time : bool
        Let Chromium run the page's timers on virtual time (20 s of it) before the screenshot and the
        DOM are taken, so that both show the page drawn. The page's clock is then virtual too, and runs
        ahead of the real one by the timers it skipped; without it the clock is real, and the page is
        read once it has loaded (a page still drawing then says nothing of being drawn).

    Returns
    -------
    dict
        ``console`` (the page's console lines), ``errors`` (those saying a resource failed to load or
        a script failed), ``drawn`` (the figures of the page's "drawn" line, or None), ``dom`` (str or None).
    """
    base = [chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            f"--window-size={WINDOW[0]},{WINDOW[1]}", "--host-resolver-rules=MAP * ~NOTFOUND",
            "--enable-logging=stderr", "--v=0", *(["--virtual-time-budget=20000"] if virtual_time else [])]
    url = f"file://{page}{fragment}"
    shot = [f"--screenshot={screenshot}"] if screenshot is not None else []
    result = subprocess.run([*base, *shot, url], capture_output=True, text=True, timeout=timeout_s)
    console = [line for line in result.stderr.splitlines() if ":CONSOLE" in line]
    drawn = [json.loads(m.group(1)) for m in map(DRAWN.search, console) if m]
    html = (subprocess.run([*base, "--dump-dom", url], capture_output=True, text=True, timeout=timeout_s).stdout
            if dom else None)
    return {"console": console, "errors": [line for line in console if "net::ERR" in line or "Uncaught" in line],
            "drawn": drawn[0] if drawn else None, "dom": html}
