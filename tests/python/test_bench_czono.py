"""bench/bench_czono.py (docs/benchmarks.md, region bench_czono) on two small cases.

The bench asserts itself that setbound's certified hull contains the one HiGHS computes on the
same LPs (it would fail if the hull, the intersection or the bench's LP formulation were wrong);
here: that it runs, writes only its own region, and reports one row per set with positive times
and the hull difference small (the same optimum by two solvers).
"""
import re

from bench_support import load_bench
from cora_support import DATA, needs_data


def _bench():
    return load_bench("bench_czono")


@needs_data
def test_bench_czono_rows_and_region(tmp_path):
    doc = tmp_path / "benchmarks.md"
    doc.write_text("# title\n\nkept\n\n<!-- bench_czono:begin -->\nold\n<!-- bench_czono:end -->\n\nkept too\n")
    rows = _bench().main(["--data", str(DATA), "--repeat", "1", "--only", "alamo", "random, n_x = 2",
                          "--out", str(doc)])
    # alamo and the random system: bounded and exact set each
    assert len(rows) == 4
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        n, ng, nc = int(cells[1]), int(cells[2]), int(cells[3])
        assert n == 2 and ng > n and nc >= 1
        t_int, t_hull, t_highs = float(cells[4]), float(cells[5]), float(cells[6])
        assert t_int > 0 and t_hull > 0 and t_highs > 0
        assert cells[7].endswith("×")
        assert float(cells[8]) < 1e-6  # |Δ| to HiGHS's optimum
    text = doc.read_text()
    assert text.startswith("# title\n\nkept\n") and text.endswith("kept too\n")
    region = re.search(r"<!-- bench_czono:begin -->\n(.*)\n<!-- bench_czono:end -->", text, re.S).group(1)
    assert "old" not in region.splitlines() and "| set | n_x |" in region
