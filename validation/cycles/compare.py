# The match check of two renders of one scene (run by Blender's Python, which reads EXR):
#   blender -b --factory-startup --python compare.py -- IMAGE.exr REFERENCE.exr DIFF.png
# prints one JSON line "COMPARE {...}" with the mean of each image, their mean difference and its
# standard error (pixels' noise is independent, so SE = std(d)/sqrt(N)) and the RMSE of the
# difference; writes the difference (mean of the channels) as a PNG, red where IMAGE is brighter,
# blue where darker, full colour at ±0.05.
import json
import sys

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:]


def load(path):
    im = bpy.data.images.load(path)
    w, h = im.size
    return np.array(im.pixels[:], dtype=np.float64).reshape(h, w, 4)[:, :, :3]


a, b = load(args[0]), load(args[1])
d = (a - b).mean(axis=2)
n = d.size
result = {
    "image_mean": float(a.mean()),
    "reference_mean": float(b.mean()),
    "mean_difference": float(d.mean()),
    "mean_difference_se": float(d.std(ddof=1) / np.sqrt(n)),
    "rmse": float(np.sqrt((d * d).mean())),
}
print("COMPARE " + json.dumps(result))

h, w = d.shape
t = np.clip(d / 0.05, -1, 1)
rgba = np.ones((h, w, 4))
rgba[:, :, 0] = 1 - np.maximum(-t, 0)
rgba[:, :, 1] = 1 - np.abs(t)
rgba[:, :, 2] = 1 - np.maximum(t, 0)
out = bpy.data.images.new("difference", w, h, alpha=False)
out.pixels[:] = rgba.ravel()  # (Blender's rows run bottom to top, as loaded)
out.filepath_raw = args[2]
out.file_format = "PNG"
out.save()
