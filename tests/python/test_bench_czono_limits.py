"""bench/bench_czono_limits.py (docs/benchmarks.md, region bench_czono_limits) on a short record.

The bench asserts itself that the bounded hull is never narrower than the exact consistent set's
(it would fail if the reduction cut into the set or the exact run were not exact) and that two
runs give the same widths; here: that it runs, writes only its own region, one row per pair of
limits, and that more generators and rows do not widen the set on this record.
"""
import re

from bench_support import load_bench
from cora_support import DATA, needs_data


@needs_data
def test_bench_czono_limits_rows_and_region(tmp_path):
    doc = tmp_path / "benchmarks.md"
    doc.write_text("# t\n\n<!-- bench_czono_limits:begin -->\nold\n<!-- bench_czono_limits:end -->\n\nkept\n")
    rows = load_bench("bench_czono_limits").main(
        ["--data", str(DATA), "--repeat", "1", "--only", "vehicle2", "--steps", "30",
         "--limits", "4,24", "8,100", "--out", str(doc)])
    assert len(rows) == 2
    ratios = []
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert cells[0] == "vehicle2_cora_unittest" and int(cells[1]) == 2 and int(cells[2]) == 30
        ratios.append(float(cells[5]))
        assert float(cells[6]) > 0
    assert 1.0 - 1e-9 <= ratios[1] <= ratios[0]
    text = doc.read_text()
    assert text.startswith("# t\n") and text.endswith("kept\n")
    region = re.search(r"<!-- bench_czono_limits:begin -->\n(.*)\n<!-- bench_czono_limits:end -->", text, re.S).group(1)
    assert "old" not in region.splitlines() and "| data | n_x | steps | limits |" in region
