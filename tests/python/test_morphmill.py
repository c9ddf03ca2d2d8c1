# SPDX-License-Identifier: Apache-2.0
"""The Python module morphmill against closed forms (run by ctest: python_module).

The single slot job: a ball end of radius 2 whose centre runs along the top face of a
40 x 20 x 10 block, so half a cylinder of radius 2 and length 40 leaves it."""
import math
import os
import unittest

import numpy as np

import morphmill

DATA = os.environ.get("MORPHMILL_TEST_DATA", os.path.join(os.path.dirname(__file__), "../../data"))
SLOT = os.path.join(DATA, "jobs", "single_slot.json")
SLOT_VOLUME = 40 * 20 * 10 - 0.5 * math.pi * 2**2 * 40


class MorphmillModule(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.job = morphmill.load_job(SLOT)
        cls.part = morphmill.erode(cls.job)

    def test_version(self):
        self.assertRegex(morphmill.version(), r"^\d+\.\d+\.\d+$")

    def test_job(self):
        self.assertEqual(self.job.name, "single_slot")
        self.assertEqual(self.job.units, "mm")
        self.assertEqual(self.job.tolerance, 0.01)
        self.assertEqual(self.job.move_count, 1)
        self.assertEqual(self.job.describe()["name"], "single_slot")

    def test_erode_gives_the_closed_form_volume_as_numpy_arrays(self):
        mesh = self.part.mesh
        self.assertTrue(self.part.valid)
        self.assertEqual(self.part.self_intersections, 0)
        vertices, triangles, tags = mesh.vertices, mesh.triangles, mesh.tags
        self.assertEqual(vertices.dtype, np.float64)
        self.assertEqual(vertices.shape, (mesh.vertex_count, 3))
        self.assertEqual(triangles.dtype, np.uint32)
        self.assertEqual(triangles.shape, (mesh.triangle_count, 3))
        self.assertEqual(tags.shape, (mesh.triangle_count, 3))
        # Volume from the arrays themselves (divergence theorem), and from the library.
        a, b, c = (vertices[triangles[:, k]] for k in range(3))
        volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
        bound = 0.01 * math.pi * 2 * 40  # tolerance times the curved area
        self.assertAlmostEqual(volume, SLOT_VOLUME, delta=bound)
        self.assertAlmostEqual(self.part.topology.volume, volume, delta=1e-6)
        # The block's bounds: nothing outside [0, 40] x [0, 20] x [0, 10].
        np.testing.assert_allclose(vertices.min(axis=0), [0, 0, 0], atol=1e-9)
        np.testing.assert_allclose(vertices.max(axis=0), [40, 20, 10], atol=1e-9)
        # Side sweep faces (kind 3) come from the only move (index 0).
        self.assertTrue(np.all(tags[tags[:, 0] == 3][:, 1] == 0))

    def test_erode_is_deterministic_and_sound(self):
        self.assertTrue(self.part.valid)
        again = morphmill.erode(self.job)
        self.assertEqual(again.topology.volume, self.part.topology.volume)
        np.testing.assert_array_equal(again.mesh.vertices, self.part.mesh.vertices)

    def test_reference_volume(self):
        reference = morphmill.reference(self.job, voxel_size=0.5)
        self.assertEqual(reference.voxel_size, 0.5)
        self.assertEqual(len(reference.piece_volumes), 1)
        # Sharp edges are cut by about a voxel: voxel^2 times their length (360 mm) bounds the loss.
        self.assertAlmostEqual(reference.volume, SLOT_VOLUME, delta=0.5**2 * 360)

    def test_deviation_of_a_moved_cube(self):
        cube = morphmill.read_mesh(os.path.join(DATA, "meshes", "cube.stl"))
        moved = morphmill.Mesh(cube.vertices + np.array([0.0, 0.0, 0.3]), cube.triangles)
        d = morphmill.deviation(cube, moved, face_samples=5000)
        self.assertAlmostEqual(d.hausdorff, 0.3, delta=1e-9)
        samples = d.a_to_b
        self.assertEqual(samples.positions.shape, (len(samples.values), 3))
        self.assertGreaterEqual(len(samples.values), 5000)
        self.assertAlmostEqual(float(np.nanmax(np.abs(samples.values))), 0.3, delta=1e-9)
        # Every sample of the cube lies on its surface: one coordinate at 0 or 10.
        on_face = np.isclose(samples.positions, 0.0, atol=1e-9) | np.isclose(samples.positions, 10.0, atol=1e-9)
        self.assertTrue(np.all(on_face.any(axis=1)))

    def test_verify(self):
        report = morphmill.verify(self.job, voxel_size=0.5, face_samples=5000)
        self.assertTrue(report.verdict)
        self.assertTrue(report.generator_within_tolerance)
        self.assertEqual(report.generator_skipped, "")
        self.assertAlmostEqual(report.agreement_bound, 0.01 + math.sqrt(3) * 0.5, places=12)
        self.assertLessEqual(report.generator_to_exact.stats.max_abs, 0.01)
        self.assertIsInstance(report.summary, dict)

    def test_errors(self):
        with self.assertRaises(morphmill.IoError) as missing:
            morphmill.load_job(os.path.join(DATA, "jobs", "no_such_job.json"))
        self.assertIn("no_such_job.json", str(missing.exception))
        flat = morphmill.load_job(os.path.join(DATA, "jobs", "tool_flat.json"))
        with self.assertRaises(morphmill.InputError):
            morphmill.erode(flat, tolerance=-1.0)
        with self.assertRaises(TypeError):  # generator= was retired with generator 1
            morphmill.erode(flat, generator=2)
        with self.assertRaises(ValueError):  # InputError is a ValueError
            morphmill.Mesh(np.zeros((3, 3)), np.array([[0, 1, 5]], dtype=np.uint32))
        with self.assertRaises(ValueError):
            morphmill.deviation(self.part.mesh, self.part.mesh, mode="sideways")


if __name__ == "__main__":
    unittest.main()
