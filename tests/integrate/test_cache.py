"""app/integrate/cache.py: only whole results are kept."""
from app.integrate import budget
from app.integrate.cache import Keyed, complete_only


def test_a_result_the_budget_cut_is_returned_but_not_kept():
    calls = []

    @complete_only(4)
    def work(x, cut):
        calls.append(x)
        if cut:
            budget.current().cut("stopped early")
        return x * 2

    with budget.limit(10.0):
        assert work(1, True) == 2 and work(1, True) == 2
    assert calls == [1, 1]                       # cut: computed again
    with budget.limit(10.0):
        assert work(2, False) == 4 and work(2, False) == 4
    assert calls == [1, 1, 2]                    # whole: computed once
    assert work.cache_info().currsize == 1


def test_a_result_that_says_it_is_incomplete_is_not_kept():
    calls = []

    @complete_only(4, complete=lambda r: r["complete"])
    def work(whole):
        calls.append(whole)
        return {"complete": whole}

    work(False), work(False), work(True), work(True)
    assert calls == [False, False, True]


def test_keyed_compares_by_key_only():
    assert Keyed([1], ("a",)) == Keyed([2], ("a",)) and hash(Keyed([1], 1)) == hash(Keyed([3], 1))
    assert Keyed([1], ("a",)) != Keyed([1], ("b",))
