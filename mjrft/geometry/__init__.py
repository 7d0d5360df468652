"""Surface elements of MuJoCo geoms, and curved-leg builders."""

from .curved_leg import add_curved_leg, arc_length, curved_leg_boxes, curved_leg_xml
from .discretize import (GEOM_TYPES, Elements, discretize_geom, element_count, estimate_elements, exposed,
                         exposed_elements, geom_element_count, geom_elements, inside_geom, mesh_element_count,
                         surface_area, to_geom_frame)
