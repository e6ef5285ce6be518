"""SPH kernels exactly as the solver defines them (q = r/h, d = dimension).

gaussian     W = s_d/h^d exp(-q^2),                     q <= 3 (support 3h)
             s_2 = 1/(pi (1 - e^-9)), s_3 = 1/(pi^1.5 (erf(3) - 6/sqrt(pi) e^-9))
cubic_spline W = s_d/h^d [1 - 1.5 q^2 + 0.75 q^3]        q < 1
                 s_d/h^d 0.25 (2 - q)^3                 1 <= q < 2 (Monaghan), s_2 = 10/(7 pi), s_3 = 1/pi
wendland_c2  W = s_d/h^d (1 - q/2)^4 (2 q + 1)           q < 2, s_2 = 7/(4 pi), s_3 = 21/(16 pi)
"""
import math

import numpy as np

_SIGMA = {
    "gaussian": {2: 1.0 / (math.pi * (1.0 - math.exp(-9.0))),
                 3: 1.0 / (math.pi ** 1.5 * (math.erf(3.0) - 6.0 / math.sqrt(math.pi) * math.exp(-9.0)))},
    "cubic_spline": {2: 10.0 / (7.0 * math.pi), 3: 1.0 / math.pi},
    "wendland_c2": {2: 7.0 / (4.0 * math.pi), 3: 21.0 / (16.0 * math.pi)},
}
_QMAX = {"gaussian": 3.0, "cubic_spline": 2.0, "wendland_c2": 2.0}


class Kernel:
    """Kernel ``name`` with smoothing length ``h`` in ``dimension`` 2 or 3.

    ``support_radius`` defaults to the kernel's own (3h, 2h, 2h); a run's field data value wins.
    """

    def __init__(self, name, h, dimension, support_radius=None):
        if name not in _SIGMA:
            raise ValueError("unknown kernel '%s' (expected one of %s)" % (name, ", ".join(sorted(_SIGMA))))
        if dimension not in (2, 3):
            raise ValueError("dimension must be 2 or 3, got %r" % (dimension,))
        if not h > 0:
            raise ValueError("smoothing length h must be > 0, got %r" % (h,))
        self.name, self.h, self.dimension = name, float(h), int(dimension)
        self.sigma = _SIGMA[name][self.dimension] / self.h ** self.dimension
        qmax_r = _QMAX[name] * self.h
        self.support_radius = float(support_radius) if support_radius else qmax_r
        # the kernel is zero beyond its own support even if the run says a larger radius
        self._rcut = min(self.support_radius, qmax_r)

    def W(self, r):
        q = np.asarray(r, dtype=float) / self.h
        if self.name == "gaussian":
            w = np.exp(-q * q)
        elif self.name == "cubic_spline":
            w = np.where(q < 1.0, 1.0 - 1.5 * q * q + 0.75 * q ** 3, 0.25 * np.clip(2.0 - q, 0.0, None) ** 3)
        else:
            w = np.clip(1.0 - 0.5 * q, 0.0, None) ** 4 * (2.0 * q + 1.0)
        return np.where(np.asarray(r) * 1.0 <= self._rcut, self.sigma * w, 0.0)

    def dWdr(self, r):
        """dW/dr (<= 0)."""
        q = np.asarray(r, dtype=float) / self.h
        if self.name == "gaussian":
            d = -2.0 * q * np.exp(-q * q)
        elif self.name == "cubic_spline":
            d = np.where(q < 1.0, -3.0 * q + 2.25 * q * q, -0.75 * np.clip(2.0 - q, 0.0, None) ** 2)
        else:
            d = -5.0 * q * np.clip(1.0 - 0.5 * q, 0.0, None) ** 3
        return np.where(np.asarray(r) * 1.0 <= self._rcut, self.sigma * d / self.h, 0.0)

    def __repr__(self):
        return "Kernel(%s, h=%g, d=%d, support=%g)" % (self.name, self.h, self.dimension, self.support_radius)


def kernel_from_fields(fields):
    """Kernel from a frame's field data (``kernel``, ``h``, ``dimension``, ``support_radius``)."""
    for key in ("kernel", "h", "dimension"):
        if key not in fields:
            raise KeyError("field data lacks '%s' (the solver writes kernel, h, dimension on every VTU)" % key)
    return Kernel(str(fields["kernel"]), float(fields["h"]), int(fields["dimension"]),
                  fields.get("support_radius"))
