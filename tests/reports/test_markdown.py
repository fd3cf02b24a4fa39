"""Markdown helpers: numbers and tables written one way."""

from neuromuscle.reports.markdown import bullets, fixed, in_ms, interval, link, sig, table, value_range


def test_numbers():
    assert sig(None) == "n/a" and sig(1234.5678) == "1.23e+03" and sig(0.0123456, 4) == "0.01235"
    assert fixed(7.936) == "7.94" and in_ms(0.2014) == "201"
    assert interval(1.0, 2.5) == "[1, 2.5]" and value_range(3.5e5, 2.92e5, 3.99e5) == "3.5e+05 (2.9e+05-4e+05)"


def test_table_and_lists():
    assert table(("a", "b"), [(1, "x"), (2.5, link("f.png"))]) == [
        "| a | b |", "|---|---|", "| 1 | x |", "| 2.5 | [f.png](f.png) |"]
    assert bullets(["one", "two"]) == ["- one", "- two"]
