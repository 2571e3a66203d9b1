"""The picture of `panoproj views` (docs/gallery/views_on_the_panorama.jpg): each view's
border drawn on the panorama where the written COLMAP camera (pycolmap reading sparse/0) says it
looks, above the views themselves. Usage: views_figure.py VIEWS_FOLDER PANORAMA OUT.jpg"""
import sys

import numpy as np
import pycolmap
from PIL import Image, ImageDraw

folder, pano_path, out = sys.argv[1:4]
pano = Image.open(pano_path).convert("RGB")
W, H = 1024, 512
top = pano.resize((W, H), Image.LANCZOS)
draw = ImageDraw.Draw(top)
rec = pycolmap.Reconstruction(f"{folder}/sparse/0")
images = sorted(rec.images.values(), key=lambda i: i.image_id)
colours = [(230, 60, 60), (240, 150, 40), (240, 220, 50), (90, 200, 80), (60, 200, 220), (70, 110, 240),
           (170, 90, 230), (240, 90, 190)]
thumbs = []
for k, image in enumerate(images):
    cam = rec.cameras[image.camera_id]
    t = np.linspace(0, 1, 200)
    edge = np.concatenate([np.column_stack([t * cam.width, 0 * t]), np.column_stack([0 * t + cam.width, t * cam.height]),
                           np.column_stack([(1 - t) * cam.width, 0 * t + cam.height]), np.column_stack([0 * t, (1 - t) * cam.height])])
    rays = np.column_stack([cam.cam_from_img(edge), np.ones(len(edge))])
    world = rays @ image.cam_from_world().rotation.matrix()  # R^T ray, row-wise
    lon, lat = np.arctan2(world[:, 0], world[:, 2]), np.arctan2(-world[:, 1], np.hypot(world[:, 0], world[:, 2]))
    x, y = (lon / (2 * np.pi) + 0.5) * W, (0.5 - lat / np.pi) * H
    colour = colours[k % len(colours)]
    for i in range(len(x) - 1):
        if abs(x[i + 1] - x[i]) < W / 2:  # not across the seam
            draw.line([(x[i], y[i]), (x[i + 1], y[i + 1])], fill=colour, width=3)
    thumb = Image.open(f"{folder}/images/{image.name}").convert("RGB")
    thumb.thumbnail((W // 4 - 8, 1000), Image.LANCZOS)
    framed = Image.new("RGB", (thumb.width + 8, thumb.height + 8), colour)
    framed.paste(thumb, (4, 4))
    thumbs.append(framed)
rows = [thumbs[i:i + 4] for i in range(0, len(thumbs), 4)]
row_h = max(t.height for t in thumbs)
sheet = Image.new("RGB", (W, H + row_h * len(rows)), (255, 255, 255))
sheet.paste(top, (0, 0))
for r, row in enumerate(rows):
    for c, t in enumerate(row):
        sheet.paste(t, (c * (W // 4), H + r * row_h))
sheet.save(out, quality=85, optimize=True)
print(out, sheet.size)
