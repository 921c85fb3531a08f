#!/usr/bin/env python3
# Writes the planner suite's scenes (docs/planner.md "The planner suite"):
# single materials that declare effects, written as a user would, over
# reliefs, meshes, views, targets and lights the cost table was not tuned
# on. `tests/planner_suite.sh` plans each with --verify on ES 3.0 and 2.0.
import json

def scene(name, relief, depth, target, camera, segments=16, size=2.4, shadow=None, light=(-0.5, 0.3, -0.8),
          uv=1.0):
    material = {"name": name, "albedo": {"color": [0.7, 0.62, 0.5]}, "height": relief, "height_scale": depth,
                "effects": {"parallax": {"max_error_texels": target}}}
    if uv != 1.0:
        material["uv"] = {"scale": [uv, uv]}
    if shadow:
        material["effects"]["shadow"] = {"mode": shadow[0], "max_error": shadow[1]}
    return {"name": name, "camera": {"position": camera, "target": [0, 0.2, 0], "fov_y_deg": 45},
            "lights": [{"type": "directional", "direction": list(light), "angular_radius_deg": 2}],
            "materials": [material],
            "objects": [{"name": "ground", "mesh": {"type": "plane", "size": size, "segments": segments},
                         "material": name}]}

low, mid, high = [0, -2.2, 0.7], [0, -2.0, 1.4], [0, -0.4, 2.6]
cases = [
    scene("bricks_low_1", {"procedural": "bricks", "size": 256}, 0.05, 1.0, low),
    scene("bricks_quad_big", {"procedural": "bricks", "size": 256}, 0.05, 1.0, [0, -3, 1.0], segments=1, size=60,
          uv=25.0),
    scene("cones_fine_05", {"procedural": "cones", "size": 256, "count": 24}, 0.08, 0.5, mid),
    scene("cones_coarse_2", {"procedural": "cones", "size": 256, "count": 4}, 0.06, 2.0, mid),
    scene("lines_thin_1", {"procedural": "lines", "size": 256, "count": 40}, 0.04, 1.0, mid),
    scene("lines_wide_4", {"procedural": "lines", "size": 256, "count": 6, "line_width": 16}, 0.06, 4.0, low),
    scene("sine_fine_05", {"procedural": "sine", "size": 256, "frequency": 24}, 0.08, 0.5, mid),
    scene("sine_broad_2", {"procedural": "sine", "size": 256, "frequency": 3}, 0.1, 2.0, low),
    scene("hemis_overhead_025", {"procedural": "hemispheres", "size": 256, "count": 6}, 0.06, 0.25, high),
    scene("text_shadow_low", {"procedural": "text", "size": 256, "text": "PARALLAX"}, 0.05, 0.5, mid,
          shadow=("hard", 0.1), light=(-0.9, 0.2, -0.25)),
    scene("pit_shadow_overhead", {"procedural": "pit", "size": 256}, 0.08, 1.0, mid, shadow=("soft", 0.08),
          light=(0, 0, -1)),
    scene("spike_tight_005", {"procedural": "spike", "size": 256}, 0.05, 0.05, mid),
    scene("bricks_shallow_4", {"procedural": "bricks", "size": 256}, 0.005, 4.0, mid),
]
for c in cases:
    with open(c["name"] + ".json", "w") as f:
        json.dump(c, f, indent=1)
        f.write("\n")
print(len(cases), "scenes")
