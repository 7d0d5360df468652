"""Surface elements of MuJoCo geoms, and curved-leg builders."""

from .curved_leg import add_curved_leg, arc_length, curved_leg_boxes, curved_leg_xml
from .discretize import Elements, GEOM_TYPES, discretize_geom, exposed, geom_elements, inside_geom, surface_area
