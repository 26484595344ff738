"""The sim-to-real section of a report (HTML), from a :func:`bench.evaluate.simreal.sim_to_real` result."""

from __future__ import annotations

import html

from bench.evaluate.simreal import sim_to_real_sentences

__all__ = ["sim_to_real_html"]


def sim_to_real_html(result: dict) -> str:
    """An HTML fragment: the sentences and the table of :func:`sim_to_real`."""
    rows = "".join(f"<tr><td>{html.escape(t['tracker'])}</td><td>{t['synthetic']:.3f}</td><td>{t['real']:.3f}</td>"
                   f"<td>{t['delta']:+.3f}</td><td>{t['rank_synthetic']:g}</td><td>{t['rank_real']:g}</td></tr>"
                   for t in result["table"])
    text = "".join(f"<p>{html.escape(s)}</p>" for s in sim_to_real_sentences(result))
    return (f"<section class='sim-to-real'><h2>Renders vs photographs</h2>{text}<table><tr><th>tracker</th>"
            f"<th>synthetic hit rate</th><th>real hit rate</th><th>real - synthetic</th><th>rank (synthetic)</th>"
            f"<th>rank (real)</th></tr>{rows}</table></section>")
