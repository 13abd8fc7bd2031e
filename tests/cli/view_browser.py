"""Drives `volstream view` in headless chromium (selenium + chromedriver): see view_browser.sh."""
import json
import re
import sys
import time

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

URL = sys.argv[1]
URL6 = sys.argv[2] if len(sys.argv) > 2 else None  # a second server, on [::1]


def browser():
    options = Options()
    options.binary_location = "/usr/bin/chromium"
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=900,600", "--no-first-run"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def viewer(driver):
    return driver.execute_script("return window.volstreamViewer || null")


def wait_for(what, condition, timeout=30):
    end = time.time() + timeout
    while time.time() < end:
        value = condition()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError("timed out waiting for " + what)


def full_frame_after(driver, frames, what):
    """The first full-resolution frame drawn after `frames` frames: its checksum and header."""
    def ready():
        v = viewer(driver)
        return v if v and v["frames"] > frames and v["last"] and not v["last"]["preview"] else None
    # Preview frames may come first; the full one follows 150 ms after the last change.
    v = wait_for(what, ready)
    time.sleep(0.4)
    v = viewer(driver)
    assert not v["last"]["preview"], what + ": last frame is a preview"
    return v


def changes(driver, action, what):
    before = viewer(driver)
    action()
    after = wait_for(what, lambda: (lambda v: v if v["checksum"] != before["checksum"] and not v["last"]["preview"]
                                    else None)(full_frame_after(driver, before["frames"], what)))
    print("ok:", what, "changes the frame")
    return after


def main():
    driver = browser()
    try:
        driver.get(URL)
        v = full_frame_after(driver, 0, "the first frame")
        assert v["checksum"] != 0, "blank frame"
        size = driver.execute_script("return [document.getElementById('view').width, document.getElementById('view').height]")
        assert v["last"]["width"] == size[0] and v["last"]["height"] == size[1], (v["last"], size)
        print("ok: image appears", size)

        canvas = driver.find_element(By.ID, "view")
        changes(driver, lambda: ActionChains(driver).move_to_element(canvas).click_and_hold()
                .move_by_offset(60, 10).move_by_offset(60, 20).release().perform(), "orbit (drag)")
        changes(driver, lambda: driver.execute_script(
            "const s = document.getElementById('step'); s.value = 2; s.dispatchEvent(new Event('input'))"),
            "time slider")
        # A frame of the drag may still land after the slider moved (slow builds, e.g. the
        # sanitizer's): wait for the full frame of step 2 rather than take the next change.
        wait_for("a full frame of step 2",
                 lambda: (lambda v: v["last"]["step"] == 2 and not v["last"]["preview"])(viewer(driver)))
        changes(driver, lambda: Select(driver.find_element(By.ID, "cmap")).select_by_visible_text("inferno"),
                "colour map")

        # Drag the most opaque point of the opacity curve halfway down (not to zero: the colour map
        # must still show below).
        last = viewer(driver)["last"]
        x, a = max(last["opacity"], key=lambda p: p[1])
        tf = driver.find_element(By.ID, "tf")
        w, h = tf.size["width"], tf.size["height"]
        start = (min(x * w, w - 2) - w / 2, (1 - min(a, 1)) * h - h / 2 + 1)
        changes(driver, lambda: ActionChains(driver).move_to_element_with_offset(tf, *start).click_and_hold()
                .move_by_offset(0, 10).move_by_offset(0, int((1 - min(a, 1)) * h / 2)).release().perform(), "opacity curve")

        # The URL carries the state: a reload shows the same step, colour map and camera.
        url = driver.current_url
        camera = viewer(driver)["last"]["camera"]
        assert "step=2" in url and "tf=inferno" in url and "cam=" in url and "opacity=" in url, url
        driver.get(url)
        v = full_frame_after(driver, 0, "the reloaded frame")
        assert v["last"]["step"] == 2 and v["last"]["tf"] == "inferno", v["last"]
        assert all(abs(p - q) < 1e-4 * (1 + abs(q)) for p, q in zip(v["last"]["camera"]["pos"], camera["pos"])), \
            (v["last"]["camera"], camera)
        print("ok: reloading the URL restores the view")

        # Play goes through the steps (the streaming pipeline), with frames/s and the slowest
        # stage shown; pausing ends with a still frame of the step shown last, and no more frames.
        driver.find_element(By.ID, "play").click()
        steps = set()
        wait_for("three steps while playing", lambda: steps.add(viewer(driver)["last"]["step"]) or len(steps) >= 3)
        # Frames/s needs two frames output before the one that shows it (under ASan on a loaded
        # machine a 30 s wait for them once ran out).
        last = wait_for("frames/s measured", lambda: (lambda h: h if h["playing"] and h.get("fps", 0) > 0 else None)(
            viewer(driver)["last"]), timeout=90)
        stats = driver.find_element(By.ID, "playStats").text
        assert re.fullmatch(r"[0-9.]+ frames/s, slowest: (read|upload|ranges|refit|render|output) [0-9.]+ ms "
                            r"\(pipeline overlap\)", stats), stats
        assert last["pipeline"] == "overlap" and last["slowest"]["ms"] > 0, last
        driver.find_element(By.ID, "play").click()
        paused = wait_for("a still frame after pause", lambda: (lambda v: v if not v["last"]["playing"] else None)(
            viewer(driver)))
        time.sleep(0.5)
        after = viewer(driver)
        assert after["frames"] == paused["frames"] and after["last"]["step"] == paused["last"]["step"], \
            (paused["last"]["step"], after["last"]["step"], after["frames"] - paused["frames"])
        assert driver.find_element(By.ID, "play").text == "play"
        print("ok: play:", stats, "; paused at step", after["last"]["step"])

        # A second tab at once.
        first = driver.current_window_handle
        driver.switch_to.new_window("tab")
        driver.get(URL)
        full_frame_after(driver, 0, "a frame in the second tab")
        driver.close()
        driver.switch_to.window(first)
        print("ok: a second tab gets frames")

        # Bad messages get an error message back; the server keeps serving.
        replies = driver.execute_async_script("""
            const done = arguments[arguments.length - 1], replies = [];
            const ws = new WebSocket('ws://' + location.host + '/ws');
            const bad = ['not json', '{"type":"view","step":99}', '{"type":"view","camera":{"pos":[0,0,0],"at":[0,0,0],"up":[0,1,0]}}',
                         '{"type":"view","pad":"' + 'x'.repeat(70000) + '"}', '{"type":"nope"}'];
            ws.onopen = () => bad.forEach((m) => ws.send(m));
            ws.onmessage = (e) => { if (typeof e.data === 'string') replies.push(JSON.parse(e.data));
                                    if (replies.length === bad.length) { ws.close(); done(replies); } };
            setTimeout(() => done(replies), 10000);""")
        assert len(replies) == 5 and all(r["type"] == "error" for r in replies), replies
        print("ok: bad messages answered:", "; ".join(r["message"] for r in replies))
        changes(driver, lambda: Select(driver.find_element(By.ID, "cmap")).select_by_visible_text("viridis"),
                "colour map after bad messages")

        if URL6:  # the page and its socket over IPv6 (the Origin check with a bracketed host)
            driver.get(URL6)
            full_frame_after(driver, 0, "a frame over IPv6")
            print("ok: a frame from", URL6)

        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert not errors, json.dumps(errors, indent=1)
        print("ok: no console errors")
    finally:
        driver.quit()


if __name__ == "__main__":
    main()
