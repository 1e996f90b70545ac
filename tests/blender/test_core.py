"""The add-on's Blender-free helpers: array shaping for drawing and baking, engine progress lines."""
import numpy as np

from many_worlds.core import arrays, engine, paths


def test_polyline_segments_join_consecutive_points_of_the_chosen_bodies():
    polyline = np.arange(2 * 3 * 3, dtype=np.float32).reshape(2, 3, 3)
    segments = arrays.polyline_segments(polyline, [1])
    assert segments.dtype == np.float32 and segments.shape == (4, 3)
    assert np.array_equal(segments, polyline[1][[0, 1, 1, 2]])
    assert arrays.polyline_segments(polyline, []).shape == (0, 3)


def test_bake_frames_cover_the_world_and_map_to_recorded_frames():
    # 121 frames at 120 Hz = 1 s = 24 frames after frame 10 at 24 fps.
    frames = arrays.bake_scene_frames(10, 24.0, 120.0, 121)
    assert frames[0] == 10 and frames[-1] == 34
    assert np.allclose(arrays.world_frame_of_scene_frame(frames, 10, 24.0, 120.0), 5 * np.arange(25))
    # 25 fps does not divide 120 Hz: fractional recorded frames, interpolated.
    assert np.allclose(arrays.world_frame_of_scene_frame([11], 10, 25.0, 120.0), [4.8])


def test_sampled_quaternions_stay_on_one_hemisphere_and_interpolate():
    q = np.array([[[1, 0, 0, 0], [-1, 0, 0, 0], [-0.8, -0.6, 0, 0]]], dtype=np.float64)
    continuous = arrays.continuous_quaternions(q)
    assert np.allclose(continuous[0], [[1, 0, 0, 0], [1, 0, 0, 0], [0.8, 0.6, 0, 0]])
    positions = np.array([[[0, 0, 0], [1, 0, 0], [2, 0, 0]]], dtype=np.float64)
    loc, rot = arrays.sample_tracks(positions, q, [0.5, 5.0])
    assert np.allclose(loc[0], [[0.5, 0, 0], [2, 0, 0]])
    assert np.allclose(np.linalg.norm(rot, axis=-1), 1)


def test_progress_lines_and_command():
    assert engine.parse_progress("MWB-PROGRESS 3 10 world 7\n") == (3, 10, 7)
    assert engine.parse_progress("mwb-engine: something") is None
    argv = engine.sample_command("/e", "s.json", "l.mwb", 5, 10, 4, 2, duration_s=3.0, stop_at_rest=False)
    assert argv[argv.index("--worlds") + 1] == "10:14"
    assert "--no-stop-at-rest" in argv and argv[argv.index("--duration") + 1] == "3.0"
    assert paths.scene_json_path("/a/shot.mwb") == "/a/shot.scene.json"
    assert paths.default_library_name("/x/shot.blend") == "shot.mwb"
