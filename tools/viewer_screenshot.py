#!/usr/bin/env python3
"""Screenshots of raycast view for the README, in headless Chromium (python3-selenium, chromium,
chromium-driver from Debian):

    python3 tools/viewer_screenshot.py build/raycast docs/images/viewer.png scenes/raytracing.txt \\
        --click 150,215 -- --shadows --transparent-shadows --bounces 8

Starts `raycast view SCENE OPTIONS` (the render options after --), waits for the image refined to 16 samples, clicks the pixel
given (row 0 at the top) to show its ray tree, and saves the page.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("raycast")
    parser.add_argument("output")
    parser.add_argument("scene")
    parser.add_argument("--click", help="X,Y of the pixel whose ray tree to show")
    parser.add_argument("--size", default="1280,760", help="window size")
    argv = sys.argv[1:]
    render_options = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    server = subprocess.Popen([os.path.abspath(args.raycast), "view", args.scene, "--port", "0", "-q"] + render_options,
                              stdout=subprocess.PIPE, text=True)
    driver = None
    try:
        url = server.stdout.readline().strip()
        options = Options()
        for argument in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                         "--disable-background-networking", "--disable-component-update", "--disable-sync",
                         "--hide-scrollbars", "--window-size=" + args.size,
                         "--user-data-dir=" + tempfile.mkdtemp(prefix="raycast-shot-")]:
            options.add_argument(argument)
        options.binary_location = "/usr/bin/chromium"
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
        driver.get(url)
        start = time.time()
        while driver.execute_script("return document.getElementById('image').dataset.spp || ''") != "16":
            if time.time() - start > 300:
                sys.exit("the image never reached 16 samples")
            time.sleep(0.2)
        if args.click:
            x, y = (int(v) for v in args.click.split(","))
            overlay = driver.find_element(By.ID, "overlay")
            width, height = overlay.size["width"], overlay.size["height"]
            ActionChains(driver).move_to_element_with_offset(overlay, x - width // 2, y - height // 2).click().perform()
            start = time.time()
            while not driver.find_elements(By.CSS_SELECTOR, "#tree li"):
                if time.time() - start > 60:
                    sys.exit("no ray tree")
                time.sleep(0.1)
            time.sleep(0.5)
        driver.save_screenshot(args.output)
    finally:
        if driver is not None:
            driver.quit()
        server.terminate()
        server.wait()


if __name__ == "__main__":
    main()
