#!/usr/bin/env python3
"""Drive headless Chromium for scripts/web.sh (standard library only).

  web_check.py run CHROMIUM URL OUT.json [--screenshot FILE.png] [--timeout S]
      Loads URL (the page with test=1) in headless Chromium, controlled through the DevTools
      protocol over --remote-debugging-pipe (no WebSocket, no npm). Waits until the page sets
      body[data-test] to "done" or "error", writes #test-result's JSON to OUT.json, and with
      --screenshot saves a PNG of the whole page.

  web_check.py compare OUT.json HOST.png HOST.pfm
      Checks that the page's canvas pixels equal the host's PNG and its linear radiance equals
      the host's PFM, byte for byte; prints one line and exits 1 on any difference.
"""

import base64
import fcntl
import json
import os
import select
import struct
import subprocess
import sys
import tempfile
import time
import zlib


class Browser:
    def __init__(self, chromium, width=1400, height=1000):
        self.profile = tempfile.TemporaryDirectory(prefix="picomis-chromium-")
        cmd_r, cmd_w = os.pipe()  # we write commands; Chromium reads them on fd 3
        res_r, res_w = os.pipe()  # Chromium writes replies on fd 4
        # Move the child's ends above 10 so that dup2 onto 3 and 4 never meets them.
        child_r = fcntl.fcntl(cmd_r, fcntl.F_DUPFD_CLOEXEC, 10)
        child_w = fcntl.fcntl(res_w, fcntl.F_DUPFD_CLOEXEC, 10)
        os.close(cmd_r)
        os.close(res_w)

        def fds():
            os.dup2(child_r, 3)  # dup2 clears close-on-exec
            os.dup2(child_w, 4)

        flags = [
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--disable-extensions", "--hide-scrollbars", "--force-device-scale-factor=1",
            f"--window-size={width},{height}", f"--user-data-dir={self.profile.name}",
            "--remote-debugging-pipe", "about:blank",
        ]
        self.proc = subprocess.Popen(
            [chromium] + flags, preexec_fn=fds, close_fds=False,
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
        )
        os.close(child_r)
        os.close(child_w)
        self.out, self.inp = cmd_w, res_r
        self.buf = b""
        self.next_id = 0
        self.events = []
        self.session = None

    def send(self, method, params=None, session=True, timeout=60):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self.out, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            reply = self.receive(deadline)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def receive(self, deadline):
        while b"\0" not in self.buf:
            if time.monotonic() > deadline:
                raise TimeoutError("no reply from Chromium")
            ready, _, _ = select.select([self.inp], [], [], 1.0)
            if ready:
                chunk = os.read(self.inp, 1 << 20)
                if not chunk:
                    err = self.proc.stderr.read().decode(errors="replace") if self.proc.poll() is not None else ""
                    raise RuntimeError(f"Chromium closed the pipe {err[-2000:]}")
                self.buf += chunk
        msg, self.buf = self.buf.split(b"\0", 1)
        return json.loads(msg)

    def attach(self):
        targets = self.send("Target.getTargets", session=False)["targetInfos"]
        page = next(t for t in targets if t["type"] == "page")
        self.session = self.send("Target.attachToTarget", {"targetId": page["targetId"], "flatten": True},
                                 session=False)["sessionId"]
        self.send("Runtime.enable")

    def evaluate(self, expression):
        r = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        return r.get("result", {}).get("value")

    def console(self):
        lines = []
        for e in self.events:
            p = e.get("params", {})
            if e.get("method") == "Runtime.consoleAPICalled":
                lines.append(" ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", [])))
            elif e.get("method") == "Runtime.exceptionThrown":
                d = p.get("exceptionDetails", {})
                lines.append(d.get("exception", {}).get("description", d.get("text", "")))
        return lines

    def close(self):
        try:
            self.send("Browser.close", session=False, timeout=10)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.profile.cleanup()


def run(chromium, url, out, screenshot=None, timeout=300.0):
    b = Browser(chromium)
    try:
        b.attach()
        b.send("Page.enable")
        b.send("Page.navigate", {"url": url})
        deadline = time.monotonic() + timeout
        state = ""
        while time.monotonic() < deadline:
            state = b.evaluate("document.body ? (document.body.dataset.test || '') : ''") or ""
            if state in ("done", "error"):
                break
            time.sleep(0.25)
        if state not in ("done", "error"):
            status = b.evaluate("document.getElementById('status') && document.getElementById('status').textContent")
            raise TimeoutError(f"the page did not finish in {timeout} s (status: {status!r}; console: {b.console()})")
        result = b.evaluate("document.getElementById('test-result').textContent")
        with open(out, "w") as f:
            f.write(result)
        if state == "error":
            raise RuntimeError(f"the page reports an error: {result} (console: {b.console()})")
        if screenshot:
            m = b.send("Page.getLayoutMetrics")["cssContentSize"]
            clip = {"x": 0, "y": 0, "width": m["width"], "height": m["height"], "scale": 1}
            shot = b.send("Page.captureScreenshot", {"format": "png", "captureBeyondViewport": True, "clip": clip})
            with open(screenshot, "wb") as f:
                f.write(base64.b64decode(shot["data"]))
    finally:
        b.close()


def read_png_rgb(path):
    """Decodes an 8-bit RGB, non-interlaced PNG (as picomis-sim writes) to (w, h, bytes)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, idat, w = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            w, h, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert (depth, color, interlace) == (8, 2, 0), f"{path}: not 8-bit RGB non-interlaced"
        elif kind == b"IDAT":
            idat += body
    raw, bpp, stride = zlib.decompress(idat), 3, 3 * w
    out, prev = bytearray(), bytearray(stride)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], (prev[i - bpp] if i >= bpp else 0)
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        prev = line
    return w, h, bytes(out)


def read_pfm_top_down(path):
    """A little-endian RGB PFM (rows bottom-up) as (w, h, f32 bytes with row 0 at the top)."""
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:
        end = pos
        while data[end:end + 1] not in (b" ", b"\n"):
            end += 1
        if end > pos:
            fields.append(data[pos:end].decode())
        pos = end + 1
    kind, w, h, scale = fields
    assert kind == "PF" and float(scale) < 0, f"{path}: not a little-endian RGB PFM"
    w, h = int(w), int(h)
    rows = [data[pos + r * w * 12:pos + (r + 1) * w * 12] for r in range(h)]
    return w, h, b"".join(reversed(rows))


def compare(result_path, png, pfm):
    r = json.load(open(result_path))
    w, h = r["width"], r["height"]
    page_rgb, page_rad = base64.b64decode(r["rgb"]), base64.b64decode(r["radiance"])
    hw, hh, host_rgb = read_png_rgb(png)
    pw, ph, host_rad = read_pfm_top_down(pfm)
    problems = []
    if (w, h) != (hw, hh) or (w, h) != (pw, ph):
        problems.append(f"sizes differ: page {w}x{h}, PNG {hw}x{hh}, PFM {pw}x{ph}")
    else:
        diff = sum(1 for i in range(w * h) if page_rgb[3 * i:3 * i + 3] != host_rgb[3 * i:3 * i + 3])
        if diff or page_rgb != host_rgb:
            problems.append(f"canvas: {diff} of {w * h} pixels differ from the host's PNG")
        diff = sum(1 for i in range(w * h) if page_rad[12 * i:12 * i + 12] != host_rad[12 * i:12 * i + 12])
        if diff or page_rad != host_rad:
            problems.append(f"radiance: {diff} of {w * h} pixels differ from the host's PFM")
    what = f"{w}x{h}, {r['spp']} spp, {len(page_rgb)} canvas bytes + {len(page_rad)} radiance bytes"
    if problems:
        print(f"FAIL {what}: " + "; ".join(problems))
        return 1
    print(f"ok   {what} equal to the host's, byte for byte ({r['samples_per_second'] / 1e6:.2f} M camera samples/s)")
    return 0


def main(argv):
    if len(argv) >= 4 and argv[0] == "run":
        args, shot, timeout = argv[1:4], None, 300.0
        rest = argv[4:]
        while rest:
            if rest[0] == "--screenshot":
                shot, rest = rest[1], rest[2:]
            elif rest[0] == "--timeout":
                timeout, rest = float(rest[1]), rest[2:]
            else:
                raise SystemExit(f"unknown argument {rest[0]}")
        run(*args, screenshot=shot, timeout=timeout)
        return 0
    if len(argv) == 4 and argv[0] == "compare":
        return compare(*argv[1:])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
