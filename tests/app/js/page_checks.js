// What a careful reader sees wrong on a drawn Streamlit page (tests/app/test_browser_pages.py).
// Returns {clipped, none, overlaps, axes, curves}: texts cut by their box, literal "None"
// shown (also an empty cell of a data frame, which the grid draws as "None"), text boxes
// drawn over one another (page text and the figures' own texts), every drawn axis with
// its title, and the step statistics of every line that is a curve (x not time).
() => {
  const out = {clipped: [], none: [], overlaps: [], axes: [], curves: []};
  const main = document.querySelector('[data-testid="stMain"]');
  const seen = e => { const r = e.getBoundingClientRect();
    return r.width > 0 && r.height > 0
      && e.checkVisibility({checkOpacity: true, checkVisibilityCSS: true}); };
  const say = e => (e.innerText || e.textContent || '').trim().replace(/\s+/g, ' ').slice(0, 80);
  const skip = '.js-plotly-plot, .katex, [data-testid="stTooltipContent"], [role="tooltip"], '
    + '[data-testid="stDataFrame"], [data-testid="stHeader"]';
  const leaves = Array.from(main.querySelectorAll('*')).filter(e =>
    !e.closest(skip) && e.tagName !== 'STYLE' && e.tagName !== 'SCRIPT'
    && Array.from(e.childNodes).some(n => n.nodeType === 3 && n.textContent.trim()) && seen(e));
  for (const e of leaves) {
    if (/(^|[\s|(:=,])None([\s|),.;]|$)/.test(e.textContent)) out.none.push(say(e));
    let a = e;
    for (let i = 0; i < 4 && a && a !== main; i++, a = a.parentElement) {
      const s = getComputedStyle(a);
      const clips = ['hidden', 'clip'].includes(s.overflowX) || s.textOverflow === 'ellipsis';
      if (clips && a.scrollWidth > a.clientWidth + 1) { out.clipped.push(say(e)); break; }
    }
  }
  // a data frame's grid draws an empty (null) cell as "None"; its accessible table has them
  main.querySelectorAll('[data-testid="stDataFrame"] table').forEach(t => {
    const heads = Array.from(t.querySelectorAll('thead th')).map(say);
    t.querySelectorAll('tbody tr').forEach(r => Array.from(r.children).forEach((c, j) => {
      if (!say(c)) out.none.push(`table column ${heads[j] || j}, row ${say(r.children[0])}`);
    }));
  });
  const boxes = [];
  // one box per drawn line: the bounding box of an inline text that wraps spans both lines
  // whole and would "overlap" the text beside it on either line
  const lines = e => { const g = document.createRange(); g.selectNodeContents(e);
    return Array.from(g.getClientRects()); };
  for (const e of leaves) for (const r of lines(e)) {
    if (r.width > 2 && r.height > 2) boxes.push({e, r, t: say(e)}); }
  const plots = Array.from(main.querySelectorAll('.js-plotly-plot'));
  plots.forEach((el, k) => {
    const fl = el._fullLayout; if (!fl) return;
    const title = ((fl.title && fl.title.text) || `figure ${k + 1}`).replace(/<[^>]+>/g, '');
    el.querySelectorAll('text.gtitle, text.annotation-text, .legendtext, text.xtitle, text.ytitle, '
      + 'text[class^="x"][class$="title"], text[class^="y"][class$="title"]').forEach(t => {
      const r = t.getBoundingClientRect();
      if (t.textContent.trim() && r.width > 1) boxes.push({e: t, r, t: `${title}: ${t.textContent.trim().slice(0, 60)}`, fig: k});
    });
    const box = el.getBoundingClientRect();
    el.querySelectorAll('text').forEach(t => { const r = t.getBoundingClientRect();
      if (t.textContent.trim() && r.width > 0
          && (r.left < box.left - 1 || r.right > box.right + 1 || r.top < box.top - 1))
        out.clipped.push(`${title}: ${t.textContent.trim().slice(0, 60)}`); });
    // the modebar drawn over the figure's title
    const bar = el.querySelector('.modebar'); const gt = el.querySelector('text.gtitle');
    if (bar && gt && seen(bar)) boxes.push({e: bar, r: bar.getBoundingClientRect(), t: `${title}: Plotly's toolbar`, fig: k});
    Object.keys(fl).filter(n => /^[xy]axis\d*$/.test(n)).forEach(n => {
      const a = fl[n]; if (!a || !a._id || a.visible === false || a.showticklabels === false) return;
      const used = el._fullData.some(t => t.visible === true && (t.xaxis === a._id || t.yaxis === a._id));
      if (!used) return;
      out.axes.push({fig: title, axis: n, title: ((a.title && a.title.text) || '').replace(/<[^>]+>/g, ''),
        type: a.type, ticks: (a._vals || []).map(v => String(v.text || '').replace(/<[^>]+>/g, ''))});
    });
    el._fullData.forEach(tr => {
      if (tr.visible !== true || !/lines/.test(tr.mode || '') || !tr.x || !tr.y || tr.x.length < 50) return;
      const ax = id => fl[id.length > 1 ? id[0] + 'axis' + id.slice(1) : id + 'axis'];
      const xa = ax(tr.xaxis), ya = ax(tr.yaxis);
      if (!xa || !ya || xa.type !== 'linear' || ya.type !== 'linear') return;
      const X = Array.from(tr.x, Number), Y = Array.from(tr.y, Number);
      const span = v => { const f = v.filter(Number.isFinite); return (Math.max(...f) - Math.min(...f)) || 1; };
      const sx = span(X), sy = span(Y), steps = [];
      for (let i = 1; i < X.length; i++) {
        const d = Math.hypot((X[i] - X[i - 1]) / sx, (Y[i] - Y[i - 1]) / sy);
        if (Number.isFinite(d)) steps.push(d);
      }
      steps.sort((a, b) => a - b);
      out.curves.push({fig: title, trace: tr.name || '', x: ((xa.title && xa.title.text) || ''),
        n: X.length, median_step: steps[Math.floor(steps.length / 2)]});
    });
  });
  for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
    const a = boxes[i], b = boxes[j];
    if (a.e.contains(b.e) || b.e.contains(a.e)) continue;
    const w = Math.min(a.r.right, b.r.right) - Math.max(a.r.left, b.r.left);
    const h = Math.min(a.r.bottom, b.r.bottom) - Math.max(a.r.top, b.r.top);
    if (w > 3 && h > 3) out.overlaps.push(`${a.t} / ${b.t}`);
  }
  return out;
}
