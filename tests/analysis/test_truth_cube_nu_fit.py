"""analysis/truth_cube_nu_fit.py: the fit takes the least RMS bead error at 5 % only,
breaks a tie towards the larger nu, and refuses a sweep of one value."""
import os
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import truth_cube_nu_fit  # noqa: E402
from results_index import ResultsError  # noqa: E402


class TruthCubeNuFit(unittest.TestCase):
    def test_the_least_error_wins_and_a_tie_goes_to_the_larger_nu(self):
        errs = {0.45: {"rms": 1.2}, 0.49: {"rms": 0.9}, 0.499: {"rms": 0.95}}
        self.assertEqual(truth_cube_nu_fit.fitted_nu(errs), 0.49)
        errs[0.499]["rms"] = 0.9
        self.assertEqual(truth_cube_nu_fit.fitted_nu(errs), 0.499)

    def test_one_value_is_no_fit(self):
        with self.assertRaises(ResultsError):
            truth_cube_nu_fit.fitted_nu({0.499: {"rms": 1.0}})


if __name__ == "__main__":
    unittest.main()
