"""The thesis's named examples under its fixed-pivot model and under the mechanics.

Run:  python docs/scripts/thesis_examples.py  (prints the Markdown table of
docs/validation.md, "The thesis's examples", which ``docs/scripts/validation.py`` runs).

The thesis (section 3.3, eq. 3.47-3.49) writes a pose with passive rotations
``x' = Rx(a) Ry(b) Rz(phi) x``, so its bolt-to-fixed rotation is the active
``Rz(phi) Ry(b) Rx(a)``: the tilt axes turn with the phase. Ours is
``Rx(roll) Ry(pitch) Rz(phase)``; the same orientation's (roll, pitch, phase) are read off
that matrix. The thesis's phase origin is taken as ours (threads in phase at 0).
"""

from __future__ import annotations

from threadmate.contact import Compliance, ContactAnalyzer, Mechanics
from threadmate.geometry import Pose, rot_x, rot_y, rot_z, spec_from_designation

#: (roll, pitch, phase) in the thesis's composition, with its verdict and where it says so.
EXAMPLES = [
    ((4.0, 0.0, 185.0), "unstable two-point (section 4.2.1, figure 4.2)"),
    ((4.0, 4.0, 235.0), "quasi-stable two-point (section 4.2.2, figure 4.3)"),
    ((-4.0, 0.0, 131.0), "stable three-point (section 4.2.3, figure 4.4)"),
    ((-4.0, 0.0, 6.0), "three contacts, 26/4/4 pairs: rolling at point 1 (figure 4.1)"),
]


def ours(alpha: float, beta: float, phi: float) -> tuple[float, float, float]:
    """The thesis's (roll, pitch, phase) in threadmate's composition (degrees)."""
    return Pose(rot_z(phi) @ rot_y(beta) @ rot_x(alpha), [0.0, 0.0, 0.0]).angles()


def main() -> None:
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    analyzer = ContactAnalyzer(spec)
    mech = Mechanics(spec, Compliance(), scene=analyzer.scene)
    soft = Mechanics(spec, Compliance(stiffness=0.01), scene=analyzer.scene)
    print(
        "| thesis (a, b, phi) | ours (roll, pitch, phase) | thesis's verdict | "
        "fixed-pivot model here | mechanics, default compliance (10 N, 1 N m/rad) | "
        "mechanics, soft compliance (0.01 N m/rad) |"
    )
    print("|---|---|---|---|---|---|")
    for (a, b, phi), verdict in EXAMPLES:
        roll, pitch, phase = ours(a, b, phi)
        fixed = analyzer.analyze(roll, pitch, phase)
        fixed_text = (
            f"{fixed.classification}{' (rolling)' if fixed.rolling else ''}; "
            f"embedding {fixed.interference:.1e} in vs drop "
            f"{fixed.origin_drop:.1e} in; {fixed.n_contacts} contacts "
            f"{fixed.region_combination}"
        )
        texts = []
        for model in (mech, soft):
            rest = model.settle(roll, pitch, phase)
            s = rest.state
            forces = ", ".join(f"{c.force:.2f}" for c in s.touching)
            texts.append(
                f"{s.classification}; tilt ({s.roll:.2f}, {s.pitch:.2f}) deg, "
                f"z_C {s.centre[2]:.5f} in; {len(s.touching)} contact(s) "
                f"{s.region_combination}, forces {forces} N; "
                f"{len(rest.path)} unstable state(s) on the way"
            )
        print(
            f"| ({a:g}, {b:g}, {phi:g}) | ({roll:.2f}, {pitch:.2f}, {phase:.2f}) | "
            f"{verdict} | {fixed_text} | {texts[0]} | {texts[1]} |"
        )


if __name__ == "__main__":
    main()
