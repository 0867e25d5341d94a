"""The lab's report: each measured property beside the intended one, Eqs. 6-7 alongside, and JSON.

Units printed: moduli in GPa, stresses in MPa, flexural rigidity per width EI/b in MN m (= MN m^2
per m of width); the JSON holds SI values (Pa, N m, m, s).
"""

from __future__ import annotations

import json
import math
import pathlib
import textwrap

from .experiments import BLOCK_SLOWER

TENSION_BENDING = "tension + bending"


def _num(v, scale: float = 1.0, unit: str = "", digits: int = 4) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{v / scale:.{digits}g}{unit}"


def _ratio(measured, intended) -> str:
    if measured is None or intended in (None, 0) or not math.isfinite(measured):
        return ""
    r = measured / intended
    return f"{r:.3f}" if abs(r) < 10 else f"{r:.3g}"


def _wrap(text: str) -> list[str]:
    """A long line of prose as lines of at most 110 characters, the continuation indented; a number and
    its unit stay together ("~" in ``text`` is a space that does not break)."""
    lines = textwrap.wrap(text, width=110, initial_indent="  ", subsequent_indent="      ", break_on_hyphens=False)
    return [line.replace("~", " ") for line in lines]


def _modes(modes: dict) -> str:
    return ", ".join(f"{n} {m}" for m, n in modes.items()) or "none"


def _row(test: str, prop: str, measured: str, intended: str, ratio: str, note: str = "") -> str:
    return f"  {test:<12}{prop:<28}{measured:>11} {intended:>11} {ratio:>6}   {note}".rstrip()


def element_size_lines(lab: dict, entry: dict) -> list[str]:
    """The table of one element size."""
    want = lab["intended"]
    d, z = entry["element_size"], entry["zhu_ji"]
    b = entry.get("bond") or {}
    GPa, MPa, MNm = 1e9, 1e6, 1e6
    lines = [f"pice lab: {lab['job']}: element size {d:g} m (h = {lab['thickness']:g} m, h/d = "
             f"{z['thickness_over_size']:.3g}, nu = {lab['poissons_ratio']:g})"]
    if b:
        cap = _num(b["compressive_strength"], MPa, " MPa") if b["compressive_strength"] else "none"
        lines.append(f"  bond springs ({b.get('calibration') or '?'} calibration): k_n {b['kn']:.4g} N/m, k_s "
                     f"{b['ks']:.4g} N/m, k_b {b['kb']:.4g} N m/rad, k_t {b['kt']:.4g} N m/rad")
        lines.append(f"  bond strength: normal {_num(b['normal_strength'], MPa, ' MPa')}, shear "
                     f"{_num(b['shear_strength'], MPa, ' MPa')}, friction {_num(b['friction'], digits=3)} "
                     f"({b.get('shear_law') or '-'}), compressive cap {cap}")
    eq6 = z["eq6_bond_strength"]
    if eq6 is not None:
        lines.append(f"  Eq. 6 (Zhu & Ji 2022): bond strength {_num(eq6, MPa, ' MPa')} for sigma_f "
                     f"{_num(want['flexural_strength'], MPa, ' MPa')} at h/d = {z['thickness_over_size']:.3g} "
                     f"(this bond: {_num(z['bond_normal_strength'], MPa, ' MPa')})")
    if z["eq7_friction"] is not None:
        ratio = want["compressive_strength"] / want["flexural_strength"]
        lines.append(f"  Eq. 7 (Zhu & Ji 2022): friction {_num(z['eq7_friction'], digits=3)} for sigma_c/sigma_f = "
                     f"{ratio:.3g} (this bond: {_num(z['bond_friction'], digits=3)})")
    lines.append(_row("test", "property", "measured", "intended", "ratio"))
    c = entry.get("compression")
    if c:
        lines.append(_row("compression", "E", _num(c["youngs_modulus"], GPa, " GPa"),
                          _num(want["youngs_modulus"], GPa, " GPa"),
                          _ratio(c["youngs_modulus"], want["youngs_modulus"]), "initial slope, extensometer"))
        lines.append(_row("", "nu", _num(c["poissons_ratio"], digits=3), _num(want["poissons_ratio"], digits=3),
                          _ratio(c["poissons_ratio"], want["poissons_ratio"]), "lateral / axial strain"))
        first = (f"first break {_num(c['stress_at_first_break'], MPa, ' MPa')} ({_modes(c['first_break_modes'])})"
                 if c["stress_at_first_break"] is not None else "no bond broke")
        if c["compressive_strength"] is not None:
            lines.append(_row("", "sigma_c (peak)", _num(c["compressive_strength"], MPa, " MPa"),
                              _num(want["compressive_strength"], MPa, " MPa"),
                              _ratio(c["compressive_strength"], want["compressive_strength"]), first))
        else:
            lines.append(_row("", "sigma_c (peak)", "> " + _num(c["largest_stress"], MPa, " MPa"),
                              _num(want["compressive_strength"], MPa, " MPa"), "", f"no peak; {first}"))
    for key, label, formula in (("three_point", "3-point", "F L^3/(48 delta)"), ("cantilever", "cantilever",
                                                                                  "F L^3/(3 delta)")):
        r = entry.get(key)
        if not r:
            continue
        beam = want["beam_rigidity"]
        plate = _num(want["plate_rigidity"], MNm, " MN m")
        lines.append(_row(label, "EI/b bending (rotations)", _num(r["rigidity_bending"], MNm, " MN m"),
                          _num(beam, MNm, " MN m"), _ratio(r["rigidity_bending"], beam),
                          f"vs E h^3/12 (free sides; plate D = {plate})"))
        app = r["rigidity_load_point"] if key == "three_point" else r["rigidity_tip"]
        what = "with the bonds' shear" if key == "three_point" else "with shear and the clamp"
        lines.append(_row("", "EI/b " + ("load point" if key == "three_point" else "tip deflection"),
                          _num(app, MNm, " MN m"), _num(beam, MNm, " MN m"), _ratio(app, beam), f"{formula}: {what}"))
        sf = r["flexural_strength"]
        where = "first break" if key == "three_point" else "root, first break"
        if sf is not None:
            lines.append(_row("", f"sigma_f ({where})", _num(sf, MPa, " MPa"), _num(want["flexural_strength"], MPa,
                                                                                      " MPa"),
                              _ratio(sf, want["flexural_strength"]), _modes(r["first_break_modes"])))
        else:
            lines.append(_row("", f"sigma_f ({where})", "> " + _num(r["largest_stress"], MPa, " MPa"),
                              _num(want["flexural_strength"], MPa, " MPa"), "", "no bond broke"))
    lines += _specimen_lines(lab, entry)
    return lines


def _specimen_lines(lab: dict, entry: dict) -> list[str]:
    """Specimens, quasi-static check and the calibration hint."""
    parts, inertia = [], []
    for key, label in (("compression", "block"), ("three_point", "3-point span"), ("cantilever", "cantilever")):
        r = entry.get(key)
        if not r:
            continue
        s = r["specimen"]
        parts.append(f"{label}~{s['length']:g}~x~{s['width']:.4g}~m ({s['rows']}~rows, {s['elements']}~elements)")
        inertia.append(f"{label.split()[0]}~{100 * r['inertia']:.2g}~%")
    lines = _wrap("specimens: " + "; ".join(parts)) if parts else []
    if inertia:
        block = f" (the block {BLOCK_SLOWER * lab['periods']:g})" if entry.get("compression") else ""
        lines += _wrap(f"quasi-static: loaded to the intended strength in {lab['periods']:g} fundamental periods"
                       f"{block} after a smooth start; up to the first break the specimen's inertia force is at most "
                       + ", ".join(inertia) + " of the load")
    r, want = entry.get("three_point"), lab["intended"]
    b = entry.get("bond") or {}
    if r and r["flexural_strength"] and want["flexural_strength"] and b.get("normal_strength") \
            and set(r["first_break_modes"]) == {TENSION_BENDING}:
        scale = want["flexural_strength"] / r["flexural_strength"]
        eq6 = entry["zhu_ji"]["eq6_bond_strength"]
        hint = (f"calibration: the beam is linear up to its first break ({TENSION_BENDING}), so sigma_f scales with "
                f"the bond's normal strength: bond.normal_strength~=~{b['normal_strength'] * scale:.4g}~Pa gives "
                f"sigma_f~=~{want['flexural_strength'] / 1e6:.4g}~MPa")
        if eq6:
            with_eq6 = r["flexural_strength"] * eq6 / b["normal_strength"]
            hint += f"; with Eq.~6's {eq6 / 1e6:.3g}~MPa it would be {with_eq6 / 1e6:.3g}~MPa"
        lines += _wrap(hint)
    return lines


def summary_lines(lab: dict) -> list[str]:
    """One line per property across the element sizes (when there are several)."""
    sizes = lab["element_sizes"]
    if len(sizes) < 2:
        return []
    want = lab["intended"]
    head = f"  {'measured / intended':<30}" + "".join(f"{'d = %g m' % e['element_size']:>12}" for e in sizes)
    lines = [f"pice lab: {lab['job']}: summary over element sizes (ratio of measured to intended)", head]
    rows = (("E (compression)", "compression", "youngs_modulus", "youngs_modulus"),
            ("sigma_c (compression)", "compression", "compressive_strength", "compressive_strength"),
            ("EI/b bending (3-point)", "three_point", "rigidity_bending", "beam_rigidity"),
            ("EI/b load point (3-point)", "three_point", "rigidity_load_point", "beam_rigidity"),
            ("sigma_f (3-point)", "three_point", "flexural_strength", "flexural_strength"),
            ("EI/b bending (cantilever)", "cantilever", "rigidity_bending", "beam_rigidity"),
            ("EI/b tip (cantilever)", "cantilever", "rigidity_tip", "beam_rigidity"),
            ("sigma_f (cantilever)", "cantilever", "flexural_strength", "flexural_strength"))
    for label, test, key, ref in rows:
        if not any(test in e for e in sizes):
            continue
        cells = [_ratio(e[test][key], want[ref]) or "-" if test in e else "" for e in sizes]
        lines.append(f"  {label:<30}" + "".join(f"{c:>12}" for c in cells))
    return lines


def report_lines(lab: dict) -> list[str]:
    """The whole printed report."""
    out = []
    for entry in lab["element_sizes"]:
        out += element_size_lines(lab, entry) + [""]
    return out + summary_lines(lab)


def _clean(v):
    """JSON-safe: NaN and inf as null, tuples as lists."""
    if isinstance(v, dict):
        return {str(k): _clean(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_clean(x) for x in v]
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def write_json(lab: dict, path) -> pathlib.Path:
    """Write the lab's results [SI] as JSON to ``path`` (folders created); returns the path."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(_clean(lab), indent=1) + "\n")
    return path
