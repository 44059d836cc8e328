"""The README's Python example: the real cloth-ball step, then the contacts per step of a
sequence, plotted with matplotlib. Run from the checkout (or give the frames folder):
    python3 tools/python/examples/cloth_ball.py [../shared/data/toi/cloth-ball/frames]"""
import sys

import matplotlib
matplotlib.use("Agg")  # draw to a file; leave out to get a window
import matplotlib.pyplot as plt

import mccd

frames = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/toi/cloth-ball/frames"
V0, F = mccd.load_mesh(f"{frames}/cloth_ball92.ply")  # V: n x 3 float64, F: m x 3 uint32
V1, _ = mccd.load_mesh(f"{frames}/cloth_ball93.ply")
scene = mccd.Scene([(V0, F)])            # copies the mesh, builds the BVH
r = scene.step([V0], [V1])               # reads V0 and V1 in place; the GIL is released
print(f"{len(r.contacts)} contacts, the earliest at t = {r.earliest_toi:.3g}")
print(r.contacts[:5])                    # kind, mesh_a, a, mesh_b, b, vertices, toi

# A sequence: a cloth dropped onto a ball (generated), stepped as `mccd run` does,
# its contacts also written to drape.csv.
run = mccd.run(scene="drape", size=4, frame_count=45, contacts="drape.csv")
steps = run.steps
plt.plot(steps["step"], steps["vf"], label="vertex-face")
plt.plot(steps["step"], steps["ee"], label="edge-edge")
plt.xlabel("step (frame k to k + 1)")
plt.ylabel("pairs in contact")
plt.legend()
plt.savefig("contacts_per_step.png")
print(run.summary)
