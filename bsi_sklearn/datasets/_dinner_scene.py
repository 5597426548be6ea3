"""The dinner-table scene: pieces, meals, participants' habits and the table's geometry."""

import numpy as np

__all__ = [
    "CENTERPIECE_XY",
    "MEALS",
    "NEGATIVE_KINDS",
    "PARTICIPANTS",
    "PIECES",
    "STACK",
    "TABLE_HEIGHT",
]

#: The eight dining-set pieces, in column order.
PIECES = (
    "dinner_plate",
    "small_plate",
    "bowl",
    "fork",
    "knife",
    "spoon",
    "water_glass",
    "mug",
)
_P = {p: k for k, p in enumerate(PIECES)}

#: The four meal configurations: which pieces the meal needs (the conditions ``pi_i``).
MEALS = {
    "dinner": ("dinner_plate", "fork", "knife", "water_glass"),
    "soup_and_salad": ("dinner_plate", "small_plate", "bowl", "fork", "spoon", "water_glass"),
    "breakfast": ("small_plate", "bowl", "knife", "spoon", "mug"),
    "full_course": PIECES,
}

#: The stacking order of the ground truth: dinner plate, then small plate, then bowl.
STACK = ("dinner_plate", "small_plate", "bowl")

#: Six simulated demonstrators and their habits. ``priority`` is the order in which they
#: like to place the pieces (None: a fresh random order each time, plates still stacked
#: correctly); ``swap_prob`` the chance of each adjacent swap of that order in a
#: demonstration; ``bimanual`` participants carry fork (left hand) and knife (right hand)
#: together; ``precision`` is the fraction of each placement tolerance they use.
PARTICIPANTS = (
    {"hand": "right", "bimanual": False, "speed": 0.75, "precision": 0.5, "swap_prob": 0.1,
     "priority": ("dinner_plate", "small_plate", "bowl", "fork", "knife", "spoon",
                  "water_glass", "mug")},
    {"hand": "left", "bimanual": False, "speed": 0.6, "precision": 0.7, "swap_prob": 0.15,
     "priority": ("water_glass", "mug", "dinner_plate", "small_plate", "bowl", "fork",
                  "spoon", "knife")},
    {"hand": "right", "bimanual": True, "speed": 0.8, "precision": 0.6, "swap_prob": 0.1,
     "priority": ("dinner_plate", "fork", "knife", "small_plate", "bowl", "spoon",
                  "water_glass", "mug")},
    {"hand": "right", "bimanual": False, "speed": 0.5, "precision": 0.4, "swap_prob": 0.05,
     "priority": ("fork", "knife", "spoon", "dinner_plate", "small_plate", "bowl", "mug",
                  "water_glass")},
    {"hand": "right", "bimanual": False, "speed": 0.65, "precision": 0.8, "swap_prob": 0.0,
     "priority": None},
    {"hand": "left", "bimanual": True, "speed": 0.7, "precision": 0.5, "swap_prob": 0.2,
     "priority": ("dinner_plate", "small_plate", "bowl", "water_glass", "mug", "fork",
                  "spoon", "knife")},
)

NEGATIVE_KINDS = ("centerpiece", "skip", "misplace", "order")

TABLE_HEIGHT = 0.75
CENTERPIECE_XY = (0.0, 0.24)
# target (x, y, yaw) of every piece on the table; plates, bowl and glass are yaw-free
_TARGETS = {
    "dinner_plate": (0.0, -0.22, 0.0),
    "small_plate": (0.0, -0.22, 0.0),
    "bowl": (0.0, -0.22, 0.0),
    "fork": (-0.19, -0.22, np.pi / 2),
    "knife": (0.17, -0.22, np.pi / 2),
    "spoon": (0.22, -0.22, np.pi / 2),
    "water_glass": (0.19, 0.0, 0.0),
    "mug": (0.31, -0.06, 0.0),
}
_THICKNESS = {"dinner_plate": 0.02, "small_plate": 0.02, "bowl": 0.05}
# where each piece waits on the side table (x, y, yaw)
_SIDE_SLOTS = {
    "dinner_plate": (0.74, -0.42, 0.0),
    "small_plate": (0.74, -0.16, 0.0),
    "bowl": (0.95, -0.42, 0.0),
    "fork": (0.90, -0.16, 0.0),
    "knife": (0.96, -0.16, 0.0),
    "spoon": (1.02, -0.16, 0.0),
    "water_glass": (1.10, -0.40, 0.0),
    "mug": (1.10, -0.26, 0.0),
}
_GRASP_HEIGHT = 0.07  # wrist above the object's base frame while holding it
_REST = {"left": (-0.3, -0.62, 0.95), "right": (0.3, -0.62, 0.95)}
_HANDS = ("left", "right")
_MOCAP_NOISE = 0.001  # metres, on tracked positions
