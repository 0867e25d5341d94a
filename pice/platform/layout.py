"""Mooring layout: where the anchors go. Each anchor is placed by the catenary layout solve
(platform.catenary.anchor_distance) at the horizontal distance where its line, at rest, pulls its
fairlead with the given pretension, over the real seabed (an anchor may sit above it); the 12-line
spread of Zhu & Ji (2022), section 4.1, is the reference layout."""

from __future__ import annotations

import math

import numpy as np

from .catenary import Segment, anchor_distance
from .mooring_lines import LineSegment

RHO_STEEL = 7850.0  # [kg/m^3], for the dry mass of lines given by their wet weight

# Table 5 of Zhu & Ji (2022), anchor first: (length [m], EA [N], D [m], wet weight [N/m])
TABLE5 = ((20.0, 675.0e6, 0.061, 0.43e3), (250.0, 900.2e6, 0.101, 0.23e3), (190.0, 700.8e6, 0.075, 0.52e3))


def table5_segments(rho_w: float = 1025.0) -> list[LineSegment]:
    """The three segments of Table 5 (anchor chain, steel cable, platform chain), anchor first."""
    return [LineSegment(length=L, ea=ea, diameter=D, wet_weight=w, dry_mass=w / 9.81 / (1.0 - rho_w / RHO_STEEL))
            for L, ea, D, w in TABLE5]


def spread_mooring(*, fairleads_body: np.ndarray, bundle_headings_deg, spread_deg: float = 5.0,
                   lines_per_bundle: int = 3, fairlead_to_anchor_height: float = 385.0,
                   pretension: float = 221.7e3, segments=None, rho_w: float = 1025.0, seabed_z: float | None = None):
    """Lines of a spread mooring around a body at rest at the origin.

    fairleads_body: (n_bundles, 3) fairlead position of each bundle (space frame at rest) [m];
    bundle_headings_deg: the outward heading of each bundle; lines of a bundle are ``spread_deg``
    apart around it. Each anchor lies ``fairlead_to_anchor_height`` below its fairlead, at the
    horizontal distance where the quasi-static line has the ``pretension`` [N] at the fairlead, over
    the seabed at height ``seabed_z`` [m] (None: each anchor sits on the seabed); fairleads at
    different heights get their own layout solve. Returns (lines as (anchor, fairlead, segments),
    the layout LineState and the horizontal anchor-fairlead distance [m] of the first fairlead).
    Raises catenary.LayoutError when no anchor distance gives the pretension.
    """
    segments = segments or table5_segments(rho_w)
    catenary = [Segment(s.length, s.wet_weight, s.ea) for s in segments]
    layouts = {}  # by the anchor's height above the seabed [m]
    lines, first = [], None
    offsets = (np.arange(lines_per_bundle) - 0.5 * (lines_per_bundle - 1)) * spread_deg
    for fl, heading in zip(np.asarray(fairleads_body, float), bundle_headings_deg):
        gap = 0.0 if seabed_z is None else max(float(fl[2]) - fairlead_to_anchor_height - seabed_z, 0.0)
        if gap not in layouts:
            layouts[gap] = anchor_distance(catenary, vertical=fairlead_to_anchor_height,
                                           fairlead_tension=pretension, anchor_height=gap)
        x, state = layouts[gap]
        first = first or (state, x)
        for off in offsets:
            a = math.radians(heading + off)
            anchor = fl + np.array([x * math.cos(a), x * math.sin(a), -fairlead_to_anchor_height])
            lines.append((anchor, fl.copy(), segments))
    return lines, first[0], first[1]


def zhu_ji_fairleads(*, length: float = 86.2, width: float = 64.6, depth: float = 15.0):
    """Fairleads at the four column corners of the semi-submersible, ``depth`` below the waterline,
    and the outward diagonal headings of the four bundles (an assumption: the paper's Fig. 11 shows
    four symmetric bundles)."""
    corners = np.array([[sx * length / 2, sy * width / 2, -depth] for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))])
    headings = [45.0, 135.0, 225.0, 315.0]
    return corners, headings
