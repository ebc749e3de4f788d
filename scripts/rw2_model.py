#!/usr/bin/env python3
"""Writes tests/fixtures/rw2/model.toml: Thomsen & Wallace's wall RW2 as a fem2rbd model.

Specimen (docs/shell-verification.md §9 gives every source):
  * Thomsen, J. H. and Wallace, J. W. (2004), "Displacement-based design of slender
    reinforced concrete structural walls - experimental verification", J. Struct. Eng.
    130(4), 618-630 (the test); the numbers below are taken as the OpenSees MVLEM example
    of the specimen states them (Kolozvari 2015, MVLEM "Example 1", OpenSees wiki and
    OpenSees/OpenSeesDocumentation source/user/manual/model/elements/MVLEM.rst):
  * 144 in tall (to the lateral load), 48 in long, 4 in thick;
  * boundary elements 7.5 in long, vertical rho 0.029333 (8 #3 bars); a 1.5 in strip
    without vertical bars inside each; web 30 in with vertical rho 0.003333 (#2 @ 7.5 in,
    two curtains), here smeared over the 33 in between the boundary elements
    (0.003333 * 30/33); horizontal web bars #2 @ 7.5 in, two curtains (rho 0.003333);
  * concrete f'c 6.2 ksi, Ec 4500 ksi, ft 0.295 ksi (unconfined); confined boundary core
    f'cc 6.9036 ksi, Ecc 5091.3 ksi (the example's calibration of the confined concrete);
  * bars: boundary fy 57.3 ksi, web fy 48.8 ksi, Es 29000 ksi, tension hardening
    b = 0.0185 (boundary) and 0.035 (web), R0 = 20, cR1 = 0.925 (SteelMPF's parameters
    of the example; Steel02 here with cR2 = 0.15, its usual value);
  * axial load 85 kips (applied by the tests, not written in the model).
Mesh: 6 columns (boundary 7.5 in, web 4 x 8.25 in, boundary 7.5 in) x 12 rows of 12 in,
ASDShellQ4 (`shell`) elements in the XZ plane, base fixed. Units SI (m, N, Pa).
"""
import pathlib
import sys

IN = 0.0254
KSI = 6.894757293168e6

H = 144 * IN
T = 4 * IN
BE = 7.5 * IN
WEB = 33 * IN
COVER = 0.75 * IN
NWEB = int(sys.argv[3]) if len(sys.argv) > 3 else 4
XS = [0.0, BE] + [BE + WEB * k / NWEB for k in range(1, NWEB)] + [BE + WEB, 2 * BE + WEB]
NZ = int(sys.argv[1]) if len(sys.argv) > 1 else 12
ZS = [H * j / NZ for j in range(NZ + 1)]

RHO_BE = 0.029333
RHO_WEB_V = 0.003333 * 30.0 / 33.0
RHO_H = 0.003333


def concrete(t, fc, e, ft):
    return (f'  {{ type = "concrete", thickness = {t!r}, E = {e!r}, nu = 0.2, '
            f'fc = {fc!r}, ft = {ft!r} }},')


def rebar(t, mat, angle):
    return f'  {{ type = "rebar", thickness = {t!r}, material = {mat}, angle = {angle} }},'


def section(tag, name, rho_v, mat_v, core):
    fc_core, e_core = core
    fc, e, ft = 6.2 * KSI, 4500 * KSI, 0.295 * KSI
    core_t = (T - 2 * COVER) / 3
    rows = [concrete(COVER, fc, e, ft), rebar(rho_v * T / 2, mat_v, 90.0),
            rebar(RHO_H * T / 2, 2, 0.0)]
    rows += [concrete(core_t, fc_core, e_core, ft)] * 3
    rows += [rebar(RHO_H * T / 2, 2, 0.0), rebar(rho_v * T / 2, mat_v, 90.0),
             concrete(COVER, fc, e, ft)]
    return "\n".join([f"[[section]]\ntag = {tag}\nname = \"{name}\"\ntype = \"layered_shell\"",
                      "density = 2400.0", "layers = ["] + rows + ["]"])


def main():
    out = [
        "# Thomsen & Wallace (2004) wall RW2 (written by scripts/rw2_model.py; sources in",
        "# docs/shell-verification.md §9). Axial load and lateral history are applied by the",
        "# tests (crates/fem2rbd-fe/tests/it/fe/shell/rw2.rs).",
        'name = "rw2"',
        "",
        "[[material]]\ntag = 1\nname = \"boundary_bars\"\ntype = \"Steel02\"",
        f"Fy = {57.3 * KSI!r}\nE0 = {29000 * KSI!r}\nb = 0.0185\nR0 = 20.0\ncR1 = 0.925\ncR2 = 0.15",
        "",
        "[[material]]\ntag = 2\nname = \"web_bars\"\ntype = \"Steel02\"",
        f"Fy = {48.8 * KSI!r}\nE0 = {29000 * KSI!r}\nb = 0.035\nR0 = 20.0\ncR1 = 0.925\ncR2 = 0.15",
        "",
        section(10, "boundary", RHO_BE, 1, (6.9036 * KSI, 5091.3 * KSI)),
        "",
        section(11, "web", RHO_WEB_V, 2, (6.2 * KSI, 4500 * KSI)),
        "",
    ]
    tag = lambda i, j: 100 * j + i + 1  # noqa: E731
    for j, z in enumerate(ZS):
        for i, x in enumerate(XS):
            out.append(f"[[node]]\ntag = {tag(i, j)}\nx = {x!r}\ny = 0.0\nz = {z!r}")
    for i in range(len(XS)):
        out.append(f"[[support]]\nnode = {tag(i, 0)}\ndofs = [1, 1, 1, 1, 1, 1]")
    e = 1
    for j in range(NZ):
        for i in range(len(XS) - 1):
            sec = 10 if i in (0, len(XS) - 2) else 11
            out.append(
                f"[[element]]\ntag = {e}\ntype_name = \"Wall\"\ngroup = 1\ntype = \"shell\"\n"
                f"nodes = [{tag(i, j)}, {tag(i + 1, j)}, {tag(i + 1, j + 1)}, {tag(i, j + 1)}]\n"
                f"section = {sec}")
            e += 1
    p = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else (
        pathlib.Path(__file__).resolve().parent.parent / "tests/fixtures/rw2/model.toml")
    p.write_text("\n".join(out) + "\n")
    print(p)


if __name__ == "__main__":
    main()
