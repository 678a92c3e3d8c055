"""End files that carry their conventions, in every format, read back by the package or by readers here.

Independent checks: the Nastran ``.bdf`` and Abaqus ``.inp`` files are parsed by small readers
written here from the formats' documentation (the package reads neither); the port receptance of
what was read is condensed here by a dense solve; a Newmark code written here attaches an exported
end using only the file's own convention fields and reproduces the package's pulse response.
Tolerances: 1e-9 relative between the receptance of what a file holds and of the M, C, K written
(the package writes doubles in full; measured 1e-12), 1e-6 relative L2 for the time history
(measured 1e-11).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

import semitrack as st
from semitrack.dynamics.signals import hann_pulse
from semitrack.fe.timedomain import pulse_response, relative_l2_error

DATA = Path(__file__).parent / "data"
F = np.geomspace(1.0, 2e4, 60)
CONVENTION_KEYS = ("side", "load_convention", "port_dofs", "port_indices", "left_end_mirror", "units", "track",
                   "band_hz", "text")


@pytest.fixture(scope="module")
def boundary():
    """A small broadband end of a viscously damped slab track (24 poles: 48 states)."""
    return st.fit_boundary(st.slab_track(damping="viscous"), band=(3.0, 3000.0), n_poles=24)


def _port_receptance(M, C, K, f=F):
    w = 2 * np.pi * f[:, None, None]
    Z = K + 1j * w * C - w ** 2 * M
    Zc = Z[:, :2, :2] - Z[:, :2, 2:] @ np.linalg.solve(Z[:, 2:, 2:], Z[:, 2:, :2])
    return np.linalg.inv(Zc)


def _close(alpha, ref, tol=1e-9):
    return np.max(np.abs(alpha - ref) / np.abs(ref)) < tol


def _written(boundary):
    """The receptance of what is written: the end's M, C, K (to the rational model itself it is
    1e-12 to 1e-9, the synthesis's own accuracy, checked in test_synthesis)."""
    return _port_receptance(*boundary.matrix_system().matrices())


def _check_conventions(conv, track=None):
    for key in CONVENTION_KEYS:
        assert key in conv, key
    assert conv["side"] == "right" and conv["load_convention"] == "applied_to_end"
    assert list(conv["port_dofs"]) == ["w", "psi"] and list(conv["port_indices"]) == [0, 1]
    assert np.array_equal(np.asarray(conv["left_end_mirror"], dtype=float), np.diag([1.0, -1.0]))
    assert "to the right of a cut" in conv["text"] and "-(Q, M)" in conv["text"] and "clockwise" in conv["text"]
    if track is not None:
        assert conv["track"] == track


def test_matrix_files_round_trip(boundary, tmp_path):
    system = boundary.matrix_system()
    ref = _written(boundary)
    for suffix in (".json", ".csv", ".mat"):
        path = st.export_system(system, tmp_path / f"end{suffix}")
        back = st.load_matrix_system(path)
        assert all(np.array_equal(a, b) for a, b in zip(back.matrices(), system.matrices())), suffix  # repr-exact
        assert _close(_port_receptance(*back.matrices()), ref), suffix
        assert back.info["track"] == boundary.track_name
    data = json.loads((tmp_path / "end.json").read_text())
    _check_conventions(data["conventions"], boundary.track_name)
    assert data["conventions"]["band_hz"] == [3.0, 3000.0]
    raw = scipy.io.loadmat(tmp_path / "end.mat")
    assert {"M", "C", "K"} <= set(raw)
    _check_conventions(json.loads(str(raw["conventions_json"][0])), boundary.track_name)


def _parse_bdf(text):
    """A reader of large-field DMIG bulk data (IFO 6, lower triangle): {name: {(row, col): value}}."""
    cards, fields = [], None
    for line in text.splitlines():
        if line.startswith("$") or not line.strip():
            continue
        if line.startswith("*"):
            fields += [line[8 + 16 * k: 8 + 16 * (k + 1)].strip() for k in range(4)]
            continue
        if fields is not None:
            cards.append(fields)
        fields = [line[:8].strip()] + [line[8 + 16 * k: 8 + 16 * (k + 1)].strip() for k in range(4)]
    cards.append(fields)
    matrices = {}
    for card in cards:
        if card[0] != "DMIG*":
            continue
        if card[2] == "0":  # the header: the matrix exists, perhaps with no entries
            matrices.setdefault(card[1], {})
            continue
        column = (int(card[2]), int(card[3]))
        terms = card[5:]
        for k in range(0, len(terms) - 2, 4):
            if terms[k]:
                row = (int(terms[k]), int(terms[k + 1]))
                value = float(terms[k + 2].replace("D", "E"))
                matrices.setdefault(card[1], {})[(row, column)] = value
    return matrices


def _dense(entries, labels):
    index = {lab: i for i, lab in enumerate(labels)}
    X = np.zeros((len(labels), len(labels)))
    for (row, col), value in entries.items():
        X[index[row], index[col]] = X[index[col], index[row]] = value
    return X


def test_nastran_dmig_reproduces_the_receptance(boundary, tmp_path):
    system = boundary.matrix_system()
    text = st.export_system(system, tmp_path / "end.bdf").read_text()
    assert "K2GG = KEND, KENDR" in text and "to the right of a cut" in text
    assert max(len(line) for line in text.splitlines()) <= 80  # Nastran reads 80 columns
    conv = json.loads("".join(line[2:] for line in text.splitlines() if line.startswith("$|")))
    _check_conventions({**conv, "text": " ".join(line[2:] for line in text.splitlines() if line.startswith("$ "))},
                       boundary.track_name)
    matrices = _parse_bdf(text)
    spoints = [int(x) for x in next(line for line in text.splitlines() if line.startswith("SPOINT")).split()[1::2]]
    labels = [(1, 2), (1, 6)] + [(p, 0) for p in range(spoints[0], spoints[1] + 1)]
    M, C, K = (_dense(matrices[f"{c}END"], labels) + _dense(matrices[f"{c}ENDR"], labels) for c in "MBK")
    # the file's axes (y up, theta_z counterclockwise) flip both ports: the port receptance is unchanged
    assert _close(_port_receptance(M, C, K), _written(boundary))
    # the remainders matter: the 16-character leading parts alone lose 3e-4 (measured)
    lead = (_dense(matrices[f"{c}END"], labels) for c in "MBK")
    assert not _close(_port_receptance(*lead), _written(boundary), 1e-6)
    assert _close(_port_receptance(M, C, K), boundary.receptance(F), 1e-8)  # the synthesis's own 9e-10


def _parse_inp(text):
    """A reader of Abaqus *MATRIX INPUT data lines (node, dof, node, dof, value; lower triangle)."""
    matrices, current = {}, None
    for line in text.splitlines():
        if line.startswith("**") or not line.strip():
            continue
        if line.startswith("*"):
            options = dict(part.strip().split("=") for part in line.split(",")[1:] if "=" in part)
            current = matrices.setdefault(options["NAME"], {}) if line.upper().startswith("*MATRIX INPUT") else None
            continue
        if current is not None:
            n1, d1, n2, d2, value = (x.strip() for x in line.split(","))
            current[((int(n1), int(d1)), (int(n2), int(d2)))] = float(value)
    return matrices


def test_abaqus_matrix_input_reproduces_the_receptance(boundary, tmp_path):
    system = boundary.matrix_system()
    text = st.export_system(system, tmp_path / "end.inp").read_text()
    assert "*MATRIX ASSEMBLE, STIFFNESS=END_K, MASS=END_M, VISCOUS DAMPING=END_C" in text
    conv = json.loads("".join(line[3:] for line in text.splitlines() if line.startswith("**|")))
    _check_conventions({**conv, "text": " ".join(line[3:] for line in text.splitlines() if line.startswith("** "))},
                       boundary.track_name)
    matrices = _parse_inp(text)
    nodes = sorted({row[0] for row, _ in matrices["END_K"]} - {1})
    labels = [(1, 2), (1, 6)] + [(n, 1) for n in nodes]
    M, C, K = (_dense(matrices[name], labels) for name in ("END_M", "END_C", "END_K"))
    assert np.array_equal(K[2:, 2:], system.K[2:, 2:])  # repr: every digit
    assert _close(_port_receptance(M, C, K), _written(boundary))


def test_paper_system_files_carry_conventions(tmp_path):
    system = st.paper_table4()
    data = json.loads(st.export_system(system, tmp_path / "t4.json", track="slab", band=(3, 900)).read_text())
    _check_conventions(data["conventions"], "slab")
    assert st.load_system_json(tmp_path / "t4.json") == system
    st.export_system(system, tmp_path / "t4.csv")
    assert "[conventions]" in (tmp_path / "t4.csv").read_text() and st.load_system_csv(tmp_path / "t4.csv") == system
    st.export_system(system, tmp_path / "t4.mat")
    _check_conventions(json.loads(str(scipy.io.loadmat(tmp_path / "t4.mat")["conventions_json"][0])))
    struct = scipy.io.loadmat(tmp_path / "t4.mat", simplify_cells=True)["conventions"]  # as MATLAB reads it
    assert struct["side"] == "right" and struct["load_convention"] == "applied_to_end"
    assert np.array_equal(struct["left_end_mirror"], np.diag([1.0, -1.0])) and list(struct["port_dofs"]) == ["w", "psi"]
    for suffix in (".bdf", ".inp"):  # the M, C, K formats take the paper's systems too
        assert "to the right of a cut" in st.export_system(system, tmp_path / f"t4{suffix}").read_text()
    text = (tmp_path / "t4.inp").read_text()
    M, C, K = (_dense(_parse_inp(text)[name], [(1, 2), (1, 6)] + [(n, 1) for n in range(9_000_001, 9_000_005)])
               for name in ("END_M", "END_C", "END_K"))
    assert _close(_port_receptance(M, C, K), system.receptance(F))


def test_boundary_files_carry_conventions_and_mck(boundary, tmp_path):
    st.save_boundary(boundary, tmp_path / "b.json")
    data = json.loads((tmp_path / "b.json").read_text())
    _check_conventions(data["conventions"], boundary.track_name)
    assert np.array_equal(data["K0"], boundary.rational.K0)  # repr-exact
    st.save_boundary(boundary, tmp_path / "b.mat")
    raw = scipy.io.loadmat(tmp_path / "b.mat", simplify_cells=True)
    second = raw["second_order"]
    assert _close(_port_receptance(second["M"], second["C"], second["K"]), _written(boundary))
    _check_conventions(json.loads(raw["conventions_json"]), boundary.track_name)
    back = st.load_boundary(tmp_path / "b.mat")
    assert np.allclose(back.receptance(F), boundary.receptance(F), rtol=1e-12)
    for fmt in ("csv", "bdf", "inp"):
        assert st.export_boundary(boundary, tmp_path / f"b.{fmt}").stat().st_size > 0
    st.export_boundary(boundary, tmp_path / "b_mck.mat", mck=True)
    assert {"M", "C", "K"} <= set(scipy.io.loadmat(tmp_path / "b_mck.mat"))
    st.export_boundary(boundary, tmp_path / "b_mck.json", mck=True)
    assert _close(_port_receptance(*st.load_matrix_system(tmp_path / "b_mck.json").matrices()), _written(boundary))


def _newmark(M, C, K, load_dof, force, dt):
    """Average-acceleration Newmark from rest, written here: displacement history of every DOF."""
    a_eff = (K + (2 / dt) * C + (4 / dt ** 2) * M).tocsc()
    solve = sp.linalg.factorized(a_eff)
    n = M.shape[0]
    u, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    out = np.zeros((force.size, n))
    for k in range(1, force.size):
        p = np.zeros(n)
        p[load_dof] = force[k]
        rhs = p + M @ ((4 / dt ** 2) * u + (4 / dt) * v + a) + C @ ((2 / dt) * u + v)
        u_new = solve(rhs)
        v_new = (2 / dt) * (u_new - u) - v
        a = (4 / dt ** 2) * (u_new - u) - (4 / dt) * v - a
        u, v = u_new, v_new
        out[k] = u
    return out


def test_a_third_party_newmark_code_attaches_the_exported_end(boundary, tmp_path):
    """A rail model with free ends, closed at both ends by the exported file read as plain JSON."""
    track = st.slab_track(damping="viscous")
    n_bays = 2
    st.export_boundary(boundary, tmp_path / "end.json", mck=True)
    data = json.loads((tmp_path / "end.json").read_text())
    conv = data["conventions"]
    assert conv["side"] == "right" and conv["load_convention"] == "applied_to_end"
    E = [np.asarray(data[name]) for name in ("M", "C", "K")]
    rail = st.TruncatedTrack(track, n_bays, ends="free")
    n_rail, n_int = rail.n_dof, E[0].shape[0] - 2
    big = [np.zeros((n_rail + 2 * n_int, n_rail + 2 * n_int)) for _ in range(3)]
    for X, R in zip(big, rail.matrices()):
        X[:n_rail, :n_rail] = R.toarray()
    ports = conv["port_indices"]
    internal = [i for i in range(E[0].shape[0]) if i not in ports]
    half = n_bays * track.spacing
    for side, x_end, first in (("right", half, n_rail), ("left", -half, n_rail + n_int)):
        # the file models a right end; a left end takes the mirror on the ports
        P = np.eye(E[0].shape[0])
        if side == "left":
            P[np.ix_(ports, ports)] = np.asarray(conv["left_end_mirror"])
        dofs = [rail.dof(x_end, "w"), rail.dof(x_end, "psi")] + list(range(first, first + n_int))
        order = list(ports) + internal
        for X, Y in zip(big, E):
            # "applied_to_end": the end's M, C, K are the load it takes, so they add to the rail's
            X[np.ix_(dofs, dofs)] += (P @ Y @ P)[np.ix_(order, order)]
    dt, t_end, f_max = 2e-5, 0.01, 1500.0
    t = dt * np.arange(int(round(t_end / dt)) + 1)
    u = _newmark(*(sp.csc_matrix(X) for X in big), rail.dof(0.0, "w"), hann_pulse(t, 2.0 / f_max), dt)
    ref = pulse_response(st.TruncatedTrack(track, n_bays, ends="boundary", system=boundary), [0.0],
                         dt=dt, duration=t_end, f_max=f_max)
    assert relative_l2_error(u[:, [rail.dof(0.0, "w")]], ref.u)[0] < 1e-6


def _words(text, comment):
    """The header's words: its comment lines joined, without their comment marks."""
    return " ".join(line[len(comment) + 1:] for line in text.splitlines() if line.startswith(f"{comment} "))


def _static_map_lines(text, comment):
    """The file's static state of the internal DOFs: {label: (T_w, T_psi)} from its comment table."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if "label, T_w (u_j per m), T_psi (u_j per rad)" in line) + 1
    rows = {}
    for line in lines[start:]:
        if not line.startswith(f"{comment} ") or "," not in line:
            break
        label, t_w, t_psi = (x.strip() for x in line[len(comment) + 1:].split(","))
        rows[int(label)] = (float(t_w), float(t_psi))
    return rows


def test_a_bdf_with_node_101_names_it_in_every_port_card_and_holds_the_static_stiffness(boundary, tmp_path):
    """``node=101`` puts the ports on grid 101 in every matrix, ``first_label`` moves the scalar points;
    the KSTAT matrices hold the 2x2 static stiffness, which equals the static condensation of the K
    read back from the same file (a dense solve here), and the listed static state is what that
    condensation puts on the internal DOFs."""
    system = boundary.matrix_system()
    text = st.export_system(system, tmp_path / "end.bdf", node=101, first_label=501).read_text()
    matrices = _parse_bdf(text)
    assert {"KEND", "KENDR", "BEND", "BENDR", "MEND", "MENDR", "KSTAT", "KSTATR"} <= set(matrices)
    n = system.n_internal
    labels = [(101, 2), (101, 6)] + [(p, 0) for p in range(501, 501 + n)]
    for name, entries in matrices.items():  # every port card on grid 101; the rest on the scalar points
        for row, col in entries:
            for grid, component in (row, col):
                assert (grid == 101 and component in (2, 6)) or (501 <= grid < 501 + n and component == 0), name
    assert any(row[0] == 101 for row, _ in matrices["KEND"]) and "SPOINT  501" in text
    assert "Ports on node 101" in text and "node 1:" not in text
    static = _dense(matrices["KSTAT"], labels[:2]) + _dense(matrices["KSTATR"], labels[:2])
    np.testing.assert_allclose(static, system.static_stiffness(), rtol=1e-13)  # both ports flip: signs cancel
    np.testing.assert_allclose(static, boundary.rational.K0, rtol=1e-8)  # the end's own static stiffness
    K = _dense(matrices["KEND"], labels) + _dense(matrices["KENDR"], labels)
    T = np.array(list(_static_map_lines(text, "$").values()))
    assert T.shape == (n, 2) and list(_static_map_lines(text, "$")) == list(range(501, 501 + n))
    # the static state leaves the internal DOFs unloaded: K_ii T + K_ip = 0, and condenses K to KSTAT
    np.testing.assert_allclose(K[2:, 2:] @ T + K[2:, :2], 0.0, atol=1e-6 * np.abs(K[2:, :2]).max())
    np.testing.assert_allclose(K[:2, :2] + K[:2, 2:] @ T, static, rtol=1e-8)


def test_an_inp_with_node_and_first_label_holds_the_static_stiffness(boundary, tmp_path):
    system = boundary.matrix_system()
    text = st.export_boundary(boundary, tmp_path / "end.inp", node=7, first_label=100).read_text()
    matrices = _parse_inp(text)
    n = system.n_internal
    labels = [(7, 2), (7, 6)] + [(p, 1) for p in range(100, 100 + n)]
    M, C, K = (_dense(matrices[name], labels) for name in ("END_M", "END_C", "END_K"))
    assert _close(_port_receptance(M, C, K), _written(boundary))
    np.testing.assert_array_equal(_dense(matrices["END_K_STATIC"], labels[:2]), system.static_stiffness())
    assert "*NODE, NSET=SEMITRACK_END_INTERNAL\n100, 0., 0., 0." in text
    assert "*MATRIX ASSEMBLE, STIFFNESS=END_K, MASS=END_M, VISCOUS DAMPING=END_C" in text  # the static one unassembled
    assert list(_static_map_lines(text, "**")) == list(range(100, 100 + n))


@pytest.mark.parametrize("options, words", [
    ({"node": 0}, "node"), ({"node": 1.5}, "node"), ({"node": True}, "node"), ({"first_label": -3}, "first_label"),
    ({"node": 9_000_010}, "lies among the internal DOFs' labels"), ({"node": 10**8}, "at most 99999999"),
    ({"first_label": 99_999_990}, "at most 99999999")])
def test_bad_labels_are_refused_by_name(boundary, tmp_path, options, words):
    with pytest.raises(st.BadInput, match=words):
        st.export_system(boundary.matrix_system(), tmp_path / "end.bdf", **options)
    assert not (tmp_path / "end.bdf").exists()


@pytest.mark.parametrize("suffix", ["json", "csv", "mat"])
def test_labels_for_a_format_that_names_dofs_are_refused_not_ignored(boundary, tmp_path, suffix):
    for call in (lambda: st.export_system(boundary.matrix_system(), tmp_path / f"e.{suffix}", node=101),
                 lambda: st.export_system(st.paper_table4(), tmp_path / f"e.{suffix}", first_label=5)):
        with pytest.raises(st.BadInput, match="label the DOFs of a .bdf or .inp file"):
            call()
    if suffix != "csv":
        with pytest.raises(st.BadInput, match="label the DOFs"):
            st.export_boundary(boundary, tmp_path / f"b.{suffix}", node=101)


def test_every_end_file_records_the_track_s_damping_and_a_hysteretic_end_warns_for_a_time_domain_code(tmp_path):
    """The fitted track's damping model travels in every format and back; writing a hysteretic
    track's end for Nastran or Abaqus warns once, naming this file's line; a viscous one does not."""
    import warnings

    hysteretic = st.fit_boundary(st.slab_track(), band=(3.0, 3000.0), n_poles=24)
    assert hysteretic.track_damping == "hysteretic"
    for suffix in ("json", "mat"):
        back = st.load_boundary(st.export_boundary(hysteretic, tmp_path / f"h.{suffix}"))
        assert back.track_damping == "hysteretic"
    for suffix in ("json", "csv", "mat"):
        back = st.load_matrix_system(st.export_boundary(hysteretic, tmp_path / f"hm.{suffix}", mck=True))
        assert back.info["track_damping"] == "hysteretic"
    assert json.loads((tmp_path / "h.json").read_text())["conventions"]["track_damping"] == "hysteretic"
    for suffix in ("bdf", "inp"):
        with pytest.warns(UserWarning, match="fitted to the hysteretic track 'slab'") as caught:
            text = st.export_boundary(hysteretic, tmp_path / f"h.{suffix}").read_text()
        assert len(caught) == 1 and caught[0].filename == __file__  # the user's line, not the package's
        assert "damping is hysteretic (loss factors, not causal)" in _words(text, "$" if suffix == "bdf" else "**")
        assert '"track_damping": "hysteretic"' in "".join(line[2 + (suffix == "inp"):] for line in text.splitlines()
                                                         if line.startswith(("$|", "**|")))
    with pytest.warns(UserWarning, match="hysteretic") as caught:  # the same warning by the other route
        st.export_system(hysteretic.matrix_system(), tmp_path / "hs.bdf")
    assert caught[0].filename == __file__
    viscous = st.load_boundary(DATA / "boundary_slab_viscous_24.json")  # a file from before the record: ""
    assert viscous.track_damping == ""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st.export_boundary(viscous, tmp_path / "v.bdf")
        fitted = st.fit_boundary(st.slab_track(damping="viscous"), band=(3.0, 3000.0), n_poles=24)
        assert st.load_boundary(st.export_boundary(fitted, tmp_path / "v.json")).track_damping == "viscous"
        st.export_boundary(fitted, tmp_path / "v.inp")
    assert "damping is viscous (causal)" in _words((tmp_path / "v.inp").read_text(), "**")


def test_an_equivalent_system_s_files_record_the_track_s_damping_and_a_hysteretic_one_warns(tmp_path):
    """The paper-style system has no record of its own: ``track_damping`` writes it in each format,
    the loaders check it, and a .bdf or .inp of a hysteretic track's system warns at the user's line."""
    import warnings

    system = st.paper_table4()  # fitted to the paper's (hysteretic) slab track
    for suffix, load in (("json", st.load_system_json), ("csv", st.load_system_csv), ("mat", st.load_system_mat)):
        path = st.export_system(system, tmp_path / f"s.{suffix}", track="slab", track_damping="hysteretic")
        assert load(path) == system
    assert json.loads((tmp_path / "s.json").read_text())["conventions"]["track_damping"] == "hysteretic"
    assert json.loads(scipy.io.loadmat(tmp_path / "s.mat")["conventions_json"][0])["track_damping"] == "hysteretic"
    for suffix in ("bdf", "inp"):
        with pytest.warns(UserWarning, match="fitted to the hysteretic track 'slab'") as caught:
            text = st.export_system(system, tmp_path / f"s.{suffix}", track="slab",
                                    track_damping="hysteretic").read_text()
        assert len(caught) == 1 and caught[0].filename == __file__
        assert "damping is hysteretic (loss factors, not causal)" in _words(text, "$" if suffix == "bdf" else "**")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st.export_system(system, tmp_path / "v.bdf", track_damping="viscous")
        st.export_system(system, tmp_path / "u.inp")  # not recorded: no warning, no claim in the file
    assert "damping is viscous (causal)" in _words((tmp_path / "v.bdf").read_text(), "$")
    assert "damping is" not in _words((tmp_path / "u.inp").read_text(), "**")
    with pytest.raises(st.BadInput, match="track_damping must be one of"):
        st.export_system(system, tmp_path / "x.json", track_damping="Hysteretic")
    data = json.loads((tmp_path / "s.json").read_text())
    data["conventions"]["track_damping"] = "coulomb"
    (tmp_path / "bad.json").write_text(json.dumps(data))
    with pytest.raises(st.BadInput, match=r"bad.json: conventions\['track_damping'\] must be one of"):
        st.load_system_json(tmp_path / "bad.json")


def test_a_file_recording_an_unknown_damping_model_is_refused(tmp_path):
    data = json.loads((DATA / "boundary_slab_viscous_24.json").read_text())
    data.setdefault("conventions", {})["track_damping"] = "coulomb"
    (tmp_path / "b.json").write_text(json.dumps(data))
    with pytest.raises(st.BadInput, match=r"conventions\['track_damping'\] must be one of"):
        st.load_boundary(tmp_path / "b.json")
