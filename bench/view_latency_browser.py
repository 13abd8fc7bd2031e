#!/usr/bin/env python3
"""Latency of `volstream view` as the page sees it, in a real browser (headless chromium).

The page sends each camera message itself (its own `send`, as a drag does) and times from
sending it to the decoded JPEG drawn on the canvas (createImageBitmap + drawImage); the viewport
is set to exactly the frame size, so the frame is WxH. Pairs each latency with the render time the
server reports. bench/view_latency.py measures the same path with a Python client.

  volstream view DATASET --port 8393 &
  /usr/bin/python3 bench/view_latency_browser.py --port 8393 --frames 40 [--size 1280x720]
"""
import os
import sys
import time

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from view_latency import orbit, parse_args, print_stats  # noqa: E402  the same orbit and figures as the Python client


# Sends the camera as a drag does and resolves once the page has drawn the next frame.
WAIT_FOR_FRAME = """
const done = arguments[arguments.length - 1], v = window.volstreamViewer, before = v.frames;
send({camera: arguments[0]}, false);
(function check() {
  if (v.frames > before) done({latency: v.latency, render_ms: v.last.render_ms});
  else setTimeout(check, 1);
})();
"""


def browser(width, height):
    options = Options()
    options.binary_location = "/usr/bin/chromium"
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--no-first-run",
                f"--window-size={width},{height}"):
        options.add_argument(arg)
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    driver.set_script_timeout(60)
    # The canvas fills the viewport: make the viewport the frame size exactly.
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                           {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})
    return driver


def wait_for(driver, what, condition, timeout=60):
    end = time.time() + timeout
    while time.time() < end:
        value = driver.execute_script(condition)
        if value:
            return value
        time.sleep(0.002)
    sys.exit("timed out waiting for " + what)


def main():
    args, width, height = parse_args()
    driver = browser(width, height)
    try:
        driver.get(f"http://{args.host}:{args.port}/")
        full = "const v = window.volstreamViewer; return v && v.last && !v.last.preview ? v : null"
        first = wait_for(driver, "the first frame", full)
        if (first["last"]["width"], first["last"]["height"]) != (width, height):
            sys.exit(f"frame is {first['last']['width']}x{first['last']['height']}, not {args.size}")
        latencies, renders = [], []
        for camera in orbit(first["last"]["camera"], args.frames):
            # Waits in the page (no polling through the driver, which would take CPU from the server).
            v = driver.execute_async_script(WAIT_FOR_FRAME, camera)
            latencies.append(v["latency"])
            renders.append(v["render_ms"])
        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        if errors:
            sys.exit("console errors: " + "; ".join(e["message"] for e in errors))
    finally:
        driver.quit()
    print(f"{args.frames} frames {width}x{height} in headless chromium")
    print_stats((("latency (page: message sent -> frame decoded and drawn)", latencies), ("render (server)", renders)))


if __name__ == "__main__":
    main()
