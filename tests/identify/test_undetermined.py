"""A parameter no output is sensitive to has an infinite standard error, not zero.

The linearised covariance is σ²(JᵀJ)⁺; with a zero Jacobian column (a valve the recording
never commands) the pseudo-inverse gives that parameter variance 0 — "known exactly" — while
the data hold no information on it at all (a crane's idle jib: `inter.dcv.s_max` ± 0 moved
30 %, and the diagnosis advised correcting the file)."""
import numpy as np

from hydrocli.diagnose.summary import nuisance_lines
from hydrocli.identify.fit import _uncertainty


class _Identity:
    """FreeParameters with z = p."""

    def dp_dz(self, z):
        return np.ones_like(z)


def test_a_parameter_with_no_sensitivity_has_an_infinite_standard_error():
    rng = np.random.default_rng(4)
    J = rng.standard_normal((200, 3))
    J[:, 1] = 0.0
    ssr, m = 2.5, 200
    se, corr = _uncertainty(None, np.zeros(3), _Identity(), ssr, m, False, J=J)
    assert np.isposinf(se[1]) and np.all(np.isnan(corr[1])) and np.all(np.isnan(corr[:, 1]))
    # the others: the closed form of the determined block, σ²(J_kᵀJ_k)⁻¹
    Jk = J[:, [0, 2]]
    ref = np.sqrt(np.diag(ssr / (m - 3) * np.linalg.inv(Jk.T @ Jk)))
    assert np.allclose(se[[0, 2]], ref, rtol=1e-12)
    assert abs(corr[0, 2]) < 1 and corr[0, 0] == 1.0


def test_the_diagnosis_advises_a_file_correction_only_where_the_data_determine_it():
    params = {"inter.dcv.s_max": {"file_value": 1000.0, "value": 700.4, "stderr": float("inf"),
                                  "change_percent": -30.0, "at_bound": "lower"},
              "outer.dcv.tau": {"file_value": 0.0333, "value": 0.0250, "stderr": 2e-4,
                                "change_percent": -24.9, "at_bound": None},
              "inner.dcv.tau": {"file_value": 0.004, "value": 0.0051, "stderr": 8e-4,
                                "change_percent": 27.5, "at_bound": None},
              "inner.dcv.s_max": {"file_value": 1000.0, "value": 997.0, "stderr": 23.0,
                                  "change_percent": -0.3, "at_bound": None}}
    lines = nuisance_lines(params)
    assert len(lines) == 3
    assert "inter.dcv.s_max: not determined" in lines[0]
    assert "outer.dcv.tau: 0.025 against the file's 0.0333 (-25 %): consider correcting" in lines[1]
    assert "inner.dcv.tau: not determined" in lines[2]          # 1.4 standard errors from the file's
