"""Titles and legend entries broken for a phone's width (issue 28, item 9)."""

from noisevar.figures._common import MODEBAR_PX, layout
from noisevar.format import LINE_CHARS, wrap_words


def test_wrap_words_breaks_at_word_boundaries():
    text = "Window tests: straight (amplitude) and not lagging (angle)"
    out = wrap_words(text)
    assert out == "Window tests: straight (amplitude)<br>and not lagging (angle)"
    assert out.replace("<br>", " ") == text
    assert all(len(line) <= LINE_CHARS for line in out.split("<br>"))
    assert wrap_words("short") == "short"
    assert wrap_words("a<br>b c", 3) == "a<br>b c"  # existing breaks kept
    assert wrap_words("x" * 50 + " y", 10) == "x" * 50 + "<br>y"  # a long word: own line


def test_layout_title_sits_under_the_toolbar_and_wraps():
    one = layout("short title")
    two = layout("Every method on fast-slow (seed 0, noise_std=5.0)")
    assert one["title"]["pad"]["t"] >= MODEBAR_PX and one["title"]["yanchor"] == "top"
    assert "<br>" in two["title"]["text"] and "<br>" not in one["title"]["text"]
    assert two["margin"]["t"] > one["margin"]["t"]  # room for the second line
