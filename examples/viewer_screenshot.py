"""A screenshot of the browser viewer (rr.view) taken with headless Chromium: the demo's
ball knocking over a pyramid, played back from a recording at t = 1 s
(docs/viewer.png). Needs ``pip install "rigidrs[view]" playwright`` and a Chromium
(``apt install chromium``); no display.

    python examples/viewer_screenshot.py [--out docs/viewer.png] [--at 1.0]
"""
from __future__ import annotations

import argparse
import shutil
import time

import numpy as np

import rigidrs as rr
from rigidrs.demo import knockdown_scene


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="docs/viewer.png")
    ap.add_argument("--at", type=float, default=1.0, help="time shown (s)")
    ap.add_argument("--size", type=int, nargs=2, default=(960, 600), metavar=("W", "H"))
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    chromium = next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)
    if chromium is None:
        raise SystemExit("no Chromium found (apt install chromium)")
    world = knockdown_scene().build(dt=1 / 120)
    rec = world.record(every=2)
    world.step(240)
    viewer = rr.view(world, rec, port=0, block=False, playing=False)
    try:
        viewer.show(int(np.argmin(np.abs(rec.times - args.at))))
        # The camera of docs/results_out.png (rr.render's picture of the same scene).
        viewer.server.initial_camera.position = (4.6, 4.2, 2.3)
        viewer.server.initial_camera.look_at = (0.0, 0.2, 0.6)
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium,
                                        args=["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox"])
            page = browser.new_page(viewport={"width": args.size[0], "height": args.size[1]})
            page.goto(viewer.url)
            page.wait_for_timeout(15000)  # software WebGL: let three.js draw everything (meshes fade in)
            # The "software WebGL" notice is true but not what the picture is about.
            page.evaluate("document.querySelectorAll('.mantine-Notification-root, .mantine-Notifications-root')"
                          ".forEach(e => e.remove())")
            t0 = time.perf_counter()
            page.screenshot(path=args.out)
            browser.close()
        print(f"wrote {args.out} (t = {rec.times[viewer.frame]:.2f} s; screenshot {time.perf_counter() - t0:.1f} s)")
    finally:
        viewer.close()


if __name__ == "__main__":
    main()
