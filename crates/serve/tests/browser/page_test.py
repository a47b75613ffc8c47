#!/usr/bin/env python3
"""The page of `fpc serve` in a real browser (headless Chromium through
Selenium): it loads without console errors; every control is reached by
the keyboard; moving the prestrain slider with the arrow keys moves the
drawn tip to where `fpc finger --eps0 X --json` puts it (to 0.01 mm); an
object too heavy to hold shows the refusal in words; an element beyond
the slope limit is marked on the drawing and named; the load path ends
where `fpc finger --fz F` puts the tip; a scene file loaded
into the page gives the grasp `fpc solve` gives on it. Saves a screenshot.

usage: page_test.py FPC_BIN SCREENSHOT.png
"""

import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys

FPC = sys.argv[1]
SHOT = sys.argv[2]
TIMEOUT = 60.0


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(what, check, timeout=TIMEOUT):
    end = time.time() + timeout
    while time.time() < end:
        value = check()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def fpc_json(*args):
    out = subprocess.run([FPC, *args], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def idle(driver):
    return driver.execute_script("return document.body.dataset.busy") == "0"


def main():
    port = free_port()
    server = subprocess.Popen(
        [FPC, "serve", "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        # the server says where it listens once it is bound
        line = server.stdout.readline()
        assert f"127.0.0.1:{port}" in line, line
        run(f"http://127.0.0.1:{port}/")
    finally:
        server.terminate()
        server.wait(timeout=10)
    print("browser test: ok")


def run(url):
    opts = webdriver.ChromeOptions()
    for a in ["--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1500,1700",
              "--disable-dev-shm-usage", "--no-first-run", "--disable-extensions"]:
        opts.add_argument(a)
    opts.binary_location = os.environ.get("CHROMIUM") or shutil.which("chromium")
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    service = Service(os.environ.get("CHROMEDRIVER") or shutil.which("chromedriver"))
    driver = webdriver.Chrome(options=opts, service=service)
    try:
        driver.get(url)
        tip = lambda: driver.find_elements(By.ID, "finger-tip")
        wait_for("the first finger", tip)
        wait_for("the curves", lambda: driver.find_elements(By.ID, "lift-object")
                 and driver.find_elements(By.CSS_SELECTOR, "#envelope-view path.curve"))
        wait_for("the page to settle", lambda: idle(driver))
        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert not errors, f"console errors on load: {errors}"
        print("loaded without console errors")

        # keyboard: Tab from the top reaches every control
        controls = driver.execute_script(
            "return [...document.querySelectorAll('input, select, textarea, button')]"
            ".filter(e => !e.disabled).map(e => e.id)")
        driver.execute_script("document.activeElement.blur(); window.focus()")
        reached = set()
        for _ in range(2 * len(controls) + 10):
            ActionChains(driver).send_keys(Keys.TAB).perform()
            reached.add(driver.switch_to.active_element.get_attribute("id"))
        missing = [c for c in controls if c not in reached]
        assert not missing, f"not reachable by Tab: {missing}"
        labelled = driver.execute_script(
            "return [...document.querySelectorAll('#controls input, #controls select')]"
            ".filter(e => !document.querySelector(`label[for='${e.id}']`)).map(e => e.id)")
        assert not labelled, f"controls without a label: {labelled}"
        print(f"Tab reaches all {len(controls)} controls, each labelled")

        # the prestrain slider moved by the arrow keys moves the tip where
        # the library's `fpc finger` puts it
        slider = driver.find_element(By.ID, "eps0")
        for presses in (6, 10):
            for _ in range(presses):
                slider.send_keys(Keys.ARROW_LEFT)
            eps0 = slider.get_attribute("value")
            got = wait_for(f"the tip at eps0 = {eps0}", lambda: driver.execute_script(
                "const t = document.getElementById('finger-tip');"
                "return t && t.dataset.eps0 === arguments[0] && document.body.dataset.busy === '0'"
                " ? [Number(t.dataset.tipXMm), Number(t.dataset.tipZMm)] : null", eps0))
            want = fpc_json("finger", "--eps0", eps0, "--json")["tip_mm"]
            assert abs(got[0] - want[0]) <= 0.01 and abs(got[1] - want[1]) <= 0.01, (eps0, got, want)
            print(f"eps0 = {eps0}: drawn tip ({got[0]:.4f}, {got[1]:.4f}) mm, fpc finger ({want[0]:.4f}, {want[1]:.4f}) mm")

        # the screenshot of the page at a valid grasp (the paper's prestrain)
        for _ in range(16):
            slider.send_keys(Keys.ARROW_RIGHT)
        assert slider.get_attribute("value") == "0.25", slider.get_attribute("value")
        wait_for("the tip at eps0 = 0.25", lambda: driver.execute_script(
            "const t = document.getElementById('finger-tip');"
            "return t && t.dataset.eps0 === '0.25' && document.body.dataset.busy === '0'"))
        wait_for("a valid grasp", lambda: "Held" in driver.find_element(By.ID, "verdict").text)
        driver.save_screenshot(SHOT)

        # too heavy: the refusal in words
        driver.execute_script(
            "const w = document.getElementById('weight'); w.value = w.max;"
            "w.dispatchEvent(new Event('input', {bubbles: true}));")
        verdict = wait_for("the refusal", lambda: (lambda v: v if v.text.startswith("Not held") and idle(driver) else None)(
            driver.find_element(By.ID, "verdict")))
        assert "invalid" in verdict.get_attribute("class"), verdict.get_attribute("class")
        assert len(verdict.text) > len("Not held: ") + 10, verdict.text
        print(f"a 12 N cuboid: {verdict.text!r}")

        # the load path, switched on from the keyboard: a tip force of 3 N
        # along +Z ends where `fpc finger --fz 3` puts the tip
        box = driver.find_element(By.ID, "path-on")
        box.send_keys(Keys.SPACE)
        assert box.is_selected()
        end = wait_for("the load path", lambda: driver.execute_script(
            "const s = document.getElementById('path-view').dataset;"
            "return document.body.dataset.busy === '0' && s.endForceN"
            " ? [Number(s.endForceN), Number(s.endTipXMm), Number(s.endTipZMm)] : null"))
        want = fpc_json("finger", "--eps0", "0.25", "--fz", "3", "--json")["tip_mm"]
        assert abs(end[0] - 3.0) < 1e-9, end
        assert abs(end[1] - want[0]) <= 0.01 and abs(end[2] - want[1]) <= 0.01, (end, want)
        print(f"load path to 3 N along +Z ends at ({end[1]:.4f}, {end[2]:.4f}) mm, fpc finger --fz 3 ({want[0]:.4f}, {want[1]:.4f}) mm")
        box.send_keys(Keys.SPACE)

        # a finding is shown where it happens: two elements turn beyond the
        # slope limit, each marked on the drawn finger and named in words
        driver.execute_script(
            "const n = document.getElementById('elements'); n.value = 2;"
            "n.dispatchEvent(new Event('input', {bubbles: true}));")
        marked = wait_for("the marked elements", lambda: driver.execute_script(
            "return document.body.dataset.busy === '0' &&"
            " [...document.querySelectorAll('#finger-view path.marked')].map(p => p.dataset.element)"))
        assert sorted(set(marked)) == ["0", "1"], marked
        words = driver.find_element(By.ID, "finger-findings").text
        assert "element 0 turns" in words and "slope limit" in words, words
        print(f"N = 2: elements {sorted(set(marked))} marked, {words.splitlines()[0]!r}")

        # a scene file loaded into the page (the file input, as a user
        # picks one) gives the grasp `fpc solve` gives on it
        scene = ("[actuator.pemc]\neps0 = 0.2\n\n[gripper]\nmounting_angle_deg = 65.0\noverlap_mm = 15.0\n\n"
                 "[gripper.grasp]\nkind = \"cuboid\"\npressure_kpa = 10.0\nd_mm = 80.0\nfriction_n = 0.2\n")
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "loaded.toml")
            with open(path, "w") as f:
                f.write(scene)
            driver.find_element(By.ID, "scene-file").send_keys(path)
            res = wait_for("the loaded scene's grasp", lambda: driver.execute_script(
                "const e = document.getElementById('scene-result');"
                "return e.dataset.normalForceN ? [e.dataset.normalForceN, e.textContent] : null"))
            assert driver.find_element(By.ID, "scene-text").get_attribute("value") == scene
            subprocess.run([FPC, "solve", path, "--out", os.path.join(d, "out")], check=True, capture_output=True)
            with open(os.path.join(d, "out", "solution.json")) as f:
                want = json.load(f)["grasp"]["normal_force_n"]
        got = float(res[0])
        assert abs(got - want) <= 1e-9 * max(1.0, abs(want)), (got, want)
        print(f"loaded scene: F = {got:.6f} N on the page, {want:.6f} N from fpc solve")

        # a design's margins carry their grasps' notes, every sample's: at
        # the paper's design the cuboid grasps bend the root element
        # backwards (allowed outside strict mode), and the page lists the
        # notes fpc design gives for each margin
        design = ("[[object]]\nkind = \"cuboid\"\nsize_mm = [90.0, 110.0]\nlift_n = 0.3\n\n"
                  "[vary]\neps0 = [0.2842, 0.2842]\nmounting_angle_deg = [74.31, 74.31]\n"
                  "overlap_mm = [20.0, 20.0]\n")
        box = driver.find_element(By.ID, "design-text")
        box.clear()
        box.send_keys(design)
        driver.find_element(By.ID, "design-run").click()
        rows = wait_for("the design's margins", lambda: driver.execute_script(
            "return [...document.querySelectorAll('#design-result tbody tr')]"
            ".map(r => [...r.cells].map(c => c.textContent))"))
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "req.toml")
            with open(path, "w") as f:
                f.write(design)
            want = fpc_json("design", path, "--json", "--starts", "0", "--out", os.path.join(d, "out"))
        want = {m["requirement"]: "; ".join(m.get("notes", [])) for m in want["margins"]}
        got = {r[0]: r[2] for r in rows}
        assert got == want, (got, want)
        noted = [r for r, n in got.items() if "bent backwards" in n]
        assert len(noted) >= 2, got
        print(f"design: {len(noted)} of {len(got)} margins noted as bent backwards, as fpc design says")
    finally:
        driver.quit()


if __name__ == "__main__":
    main()
