"""``solver.condense`` is K[keep][:, keep], including empty rows at the ends and an all-fixed corner."""
import numpy as np
import pytest
import scipy.sparse as sp

from strainwave.fea.solver import condense


@pytest.mark.parametrize("n", [1, 7, 60, 300])
def test_condense_equals_fancy_indexing(n):
    rng = np.random.default_rng(n)
    A = sp.random(n, n, density=0.08, random_state=n, format="csr")
    A = (A + A.T).tocsr()
    for _ in range(4):
        keep = rng.random(n) < 0.6
        got, want = condense(A, keep), A[keep][:, keep]
        assert got.shape == want.shape
        assert abs(got - want).sum() == 0.0
        assert got.has_sorted_indices or got.nnz == 0


def test_condense_with_empty_rows_last():
    A = sp.csr_matrix(np.diag([1.0, 2.0, 0.0, 0.0]))
    A.eliminate_zeros()
    np.testing.assert_array_equal(condense(A, np.array([True, False, True, True])).toarray(),
                                  [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    assert condense(sp.csr_matrix((3, 3)), np.array([True, True, False])).shape == (2, 2)
