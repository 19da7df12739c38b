"""The built documentation site (``make docs`` → ``site/``) in a real browser: headless Chromium
(Debian's ``chromium``) opens every page, and the test fails on a broken link, a missing image,
stylesheet or script, or a JavaScript error.

How: the site is served by a local HTTP server that adds one script at the top of every page it
serves (the files on disk are not changed); the script records the page's errors (uncaught
exceptions, rejected promises, and resources that fail to load: the ``error`` events a window
captures). A crawler page, served beside the site, opens each page in a frame, waits for it,
reads what was recorded, checks that every image has decoded (natural width > 0), fetches every
same-site link once, and posts the report back to the server. The negative control runs the same
crawl on a small site with one fault of each kind and must find all three.
"""
import json
import shutil
import subprocess
import tempfile
import threading
from functools import partial
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path


ROOT = Path(__file__).resolve().parents[2]
SITE = ROOT / "site"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--mute-audio"]

RECORDER = b"""<script>window.__errors = [];
addEventListener('error', function (e) {
  var t = e.target;
  if (t && t !== window && (t.src || t.href)) __errors.push('failed to load ' + (t.src || t.href));
  else __errors.push('JavaScript error: ' + e.message + ' (' + e.filename + ':' + e.lineno + ')');
}, true);
addEventListener('unhandledrejection', function (e) { __errors.push('unhandled rejection: ' + e.reason); });
</script>"""

CRAWLER = """<!doctype html><html><body><iframe id="f" style="width:1200px;height:900px"></iframe>
<script>
const pages = %s;
const report = {pages: 0, errors: [], links: 0};
const links = new Set();
function visit(url) {
  return new Promise(function (done) {
    const f = document.getElementById('f');
    const timer = setTimeout(function () { report.errors.push(url + ': did not load in 30 s'); done(); }, 30000);
    f.onload = function () {
      setTimeout(function () {
        clearTimeout(timer);
        const w = f.contentWindow, d = f.contentDocument;
        (w.__errors || [url + ': the recorder did not run']).forEach(function (e) { report.errors.push(url + ': ' + e); });
        d.querySelectorAll('img').forEach(function (img) {
          if (!img.complete || img.naturalWidth === 0) report.errors.push(url + ': image not shown ' + img.getAttribute('src'));
        });
        d.querySelectorAll('a[href]').forEach(function (a) {
          const u = new URL(a.getAttribute('href'), w.location.href);
          if (u.origin === location.origin) { u.hash = ''; links.add(u.href + '\\u0000' + url); }
        });
        report.pages += 1;
        done();
      }, 300);
    };
    f.src = url;
  });
}
(async function () {
  for (const p of pages) await visit(p);
  const seen = new Map();
  for (const entry of links) {
    const [href, from] = entry.split('\\u0000');
    if (!seen.has(href)) {
      let status = 0;
      try { status = (await fetch(href, {method: 'HEAD'})).status; } catch (e) { status = -1; }
      seen.set(href, status);
    }
    if (seen.get(href) !== 200) report.errors.push(from + ': broken link ' + href + ' (' + seen.get(href) + ')');
  }
  report.links = seen.size;
  await fetch('/__report', {method: 'POST', body: JSON.stringify(report)});
})();
</script></body></html>"""


def crawl(site: Path, pages, timeout: float = 900) -> dict:
    """Serve ``site``, open ``pages`` (paths relative to it) in headless Chromium, return the
    crawler's report. A missing Chromium fails (make test installs it), never skips."""
    assert CHROMIUM, "chromium is not installed: make test installs it (APT_PACKAGES)"
    got = {}
    done = threading.Event()
    crawler = (CRAWLER % json.dumps(["/" + p for p in pages])).encode()

    class Handler(SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

        def do_POST(self):
            body = self.rfile.read(int(self.headers["Content-Length"]))
            got.update(json.loads(body))
            self.send_response(204)
            self.end_headers()
            done.set()

        def do_GET(self):
            if self.path == "/__crawl.html":
                return self._send(crawler)
            path = Path(self.translate_path(self.path))
            if path.is_dir():
                path = path / "index.html"
            if path.suffix == ".html" and path.is_file():
                html = path.read_bytes()
                head = html.find(b"<head>")
                at = head + len(b"<head>") if head >= 0 else 0
                return self._send(html[:at] + RECORDER + html[at:])
            return super().do_GET()

        def _send(self, data):
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(data)))
            self.end_headers()
            self.wfile.write(data)

    server = ThreadingHTTPServer(("127.0.0.1", 0), partial(Handler, directory=str(site)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    profile = tempfile.mkdtemp(prefix="easyidp-chromium-")
    url = f"http://127.0.0.1:{server.server_address[1]}/__crawl.html"
    browser = subprocess.Popen([CHROMIUM, *FLAGS, f"--user-data-dir={profile}", url],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        finished = done.wait(timeout)
    finally:
        browser.kill()
        _, err = browser.communicate()
        server.shutdown()
        server.server_close()
        shutil.rmtree(profile, ignore_errors=True)
    assert finished, f"the crawl did not report in {timeout:.0f} s; Chromium said:\n{err[-2000:]}"
    return got


def test_the_crawl_finds_each_kind_of_fault(tmp_path):
    """Negative control: one broken link, one missing image, one JavaScript error, each found."""
    (tmp_path / "ok.png").write_bytes(Path(ROOT / "docs" / "demo_overview.png").read_bytes())
    (tmp_path / "a.html").write_text(
        '<html><head><title>a</title></head><body><img src="ok.png"><a href="b.html">b</a>'
        '<a href="gone.html">gone</a></body></html>')
    (tmp_path / "b.html").write_text(
        '<html><head><title>b</title></head><body><img src="missing.png">'
        '<script>undefinedFunction();</script></body></html>')
    report = crawl(tmp_path, ["a.html", "b.html"], timeout=120)
    errors = "\n".join(report["errors"])
    assert report["pages"] == 2
    assert "a.html: broken link" in errors and "gone.html" in errors
    assert "missing.png" in errors
    assert "JavaScript error" in errors and "undefinedFunction" in errors
    assert "ok.png" not in errors and "b.html (" not in errors
    assert len(report["errors"]) == 4   # the link, the image (failed to load, not shown), the error


def test_every_page_of_the_site_in_chromium():
    assert (SITE / "index.html").is_file(), "no site/: run make docs (make test builds it first)"
    pages = sorted(p.relative_to(SITE).as_posix() for p in SITE.rglob("*.html")
                   if p.name != "404.html")
    assert len(pages) > 40, pages
    for lang in ("zh", "ja"):
        assert f"{lang}/index.html" in pages
    report = crawl(SITE, pages)
    assert report["pages"] == len(pages)
    assert report["links"] > 50
    assert not report["errors"], "\n".join(report["errors"][:40])
