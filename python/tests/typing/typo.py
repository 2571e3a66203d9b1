"""Mistakes a type checker must catch (python/tests/test_typing.py counts one error a line)."""
import numpy as np

import panoproj as pp

pano = np.zeros((64, 128, 3), np.uint8)
pp.convert(pano, "equirect", "pinhole", interp="linaer")  # error: not an Interp
pp.Fisheye(model="equisolide")  # error: not a lens law
pp.Fisheye(fv=180)  # error: no such key
pp.convert(pano, "equirect", "pinhole", intrp="bilinear")  # error: no such option
