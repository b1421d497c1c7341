"""Game state: balls, layouts, shots and shot results."""

from pix2pockets.state.ball import CLASS_CAPS, Ball, BallClass, Group, class_of_number, parse_ball_class
from pix2pockets.state.layout import TableLayout
from pix2pockets.state.layout_file import layout_from_dict, layout_to_dict, load_layout, save_layout
from pix2pockets.state.racks import eight_ball_rack, rack_positions, random_layout
from pix2pockets.state.result import Event, EventType, ShotResult
from pix2pockets.state.shot import Shot

__all__ = [
    "CLASS_CAPS",
    "Ball",
    "BallClass",
    "Event",
    "EventType",
    "Group",
    "Shot",
    "ShotResult",
    "TableLayout",
    "class_of_number",
    "eight_ball_rack",
    "layout_from_dict",
    "layout_to_dict",
    "load_layout",
    "parse_ball_class",
    "rack_positions",
    "random_layout",
    "save_layout",
]
