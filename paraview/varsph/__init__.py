"""varsph post-processing: the logic behind the ParaView plugin ``varsph_filters.py``.

Plain numpy functions (testable without the GUI) plus readers for the run directory written by
``varsph run`` (see docs/paraview.md and shared/design/CONTRACT.md).
"""
from .kernels import Kernel, kernel_from_fields
from .io import Frame, read_pvd, read_vtu, read_dataset, read_run, frames_of_run, find_pvd, frame_from_vtk
from .freesurface import free_surface, colour_field_image, surface_mesh
from .probe import probe_pressure, probe_series, smooth_field
from .deviation import match_by_id, deviation_frame, deviation_series, common_times, DEVIATION_COLUMNS
from .surge import surge_front, water_height, surge_series

__all__ = [
    "Kernel", "kernel_from_fields", "Frame", "read_pvd", "read_vtu", "read_run", "frames_of_run",
    "find_pvd", "frame_from_vtk", "read_dataset", "smooth_field", "free_surface", "colour_field_image", "surface_mesh",
    "probe_pressure", "probe_series", "match_by_id", "deviation_frame", "deviation_series",
    "DEVIATION_COLUMNS", "surge_front", "water_height", "surge_series",
]
