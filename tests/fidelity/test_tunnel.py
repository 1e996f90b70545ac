"""No convex piece passes through a passive mesh ground: 200 sampled worlds of a Cell Fracture
wall on a MESH plane (the benchmark tunnel_worlds_per_1000 measures the same)."""

import tunnel


def test_no_piece_of_a_fractured_wall_sinks_through_a_mesh_ground_in_200_worlds():
    pieces, stored, tunnelled_worlds, tunnelled_pieces = tunnel.sample_fracture_wall_on_mesh(200)
    assert pieces >= 10 and stored == 200
    assert tunnelled_worlds == 0, f"{tunnelled_pieces} pieces sank through the ground in {tunnelled_worlds} of 200 worlds"
