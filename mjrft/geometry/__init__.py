"""Surface discretisation of MuJoCo geoms into resistive-force-theory elements."""

from .discretize import Elements, GEOM_TYPES, discretize_geom, geom_elements, surface_area
