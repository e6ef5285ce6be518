"""Kernel constants: each kernel integrates to 1 over its support (2D, 3D), W(0) and the support radius
match the definitions in the solver's contract, dW/dr is the derivative of W."""
import math

import numpy as np

import tcommon as T
from varsph.kernels import Kernel

for name, qmax in (("gaussian", 3.0), ("cubic_spline", 2.0), ("wendland_c2", 2.0)):
    for d in (2, 3):
        k = Kernel(name, 0.7, d)
        r = np.linspace(0.0, qmax * 0.7, 200001)
        shell = 2 * math.pi * r if d == 2 else 4 * math.pi * r * r
        integral = np.trapz(k.W(r) * shell, r)
        T.close(integral, 1.0, 1e-6, "%s %dD: integral of W" % (name, d))
        T.close(k.support_radius, qmax * 0.7, 1e-15, "%s %dD: support radius" % (name, d))
        T.check(k.W(qmax * 0.7 * 1.0001) == 0.0, "%s %dD: zero beyond the support" % (name, d))
        rr = np.linspace(0.05, qmax * 0.7 - 0.05, 50)
        num = (k.W(rr + 1e-6) - k.W(rr - 1e-6)) / 2e-6
        T.check(np.allclose(k.dWdr(rr), num, rtol=1e-5, atol=1e-8), "%s %dD: dW/dr" % (name, d))
T.close(Kernel("cubic_spline", 1.0, 2).W(0.0), 10 / (7 * math.pi), 1e-15, "cubic 2D W(0) = 10/(7 pi)")
T.close(Kernel("wendland_c2", 1.0, 3).W(0.0), 21 / (16 * math.pi), 1e-15, "wendland 3D W(0) = 21/(16 pi)")
T.finish()
