// The Charts page (/charts): what `make charts` measured, read from the chart
// index (charts/index.json, an rt.ChartIndex) that the build copies from
// docs/charts beside the pictures, tables and CSVs. Each section: its summary
// and machine, then per chart its picture, headline and key figures.
import { fromJson } from "@bufbuild/protobuf";
import { schema } from "./proto.js";

const FILES = "/charts";
const $ = (id) => document.getElementById(id);

function element(tag, props = {}, children = []) {
  const node = Object.assign(document.createElement(tag), props);
  node.append(...children);
  return node;
}

function renderTable(table, caption) {
  const head = element("tr", {}, table.columns.map((c) => element("th", { scope: "col", textContent: c })));
  const rows = table.rows.map((r) => element("tr", {}, r.cells.map((c, i) =>
    element(i === 0 ? "th" : "td", i === 0 ? { scope: "row", textContent: c } : { textContent: c }))));
  return element("div", { className: "chart-table" }, [
    element("table", {}, [element("caption", { textContent: caption }), element("thead", {}, [head]),
      element("tbody", {}, rows)]),
  ]);
}

function renderChart(chart) {
  const figure = element("figure", { className: "chart", id: chart.slug }, [
    element("h3", {}, [element("a", { href: `#${chart.slug}`, textContent: chart.title })]),
    element("a", { href: `${FILES}/${chart.slug}.png`, className: "chart-picture" }, [
      element("img", { src: `${FILES}/${chart.slug}.png`, alt: `${chart.title}: ${chart.headline}`, loading: "lazy" }),
    ]),
    element("figcaption", { textContent: chart.headline }),
  ]);
  if (chart.table?.columns.length) figure.append(renderTable(chart.table, `${chart.title}: key figures`));
  figure.append(element("p", { className: "chart-links" }, [
    element("a", { href: `${FILES}/${chart.slug}.csv`, textContent: "CSV (every point)", download: "" }),
    " · ",
    element("a", { href: `${FILES}/${chart.slug}.md`, textContent: "Markdown table" }),
  ]));
  return figure;
}

function renderSection(section) {
  return element("section", { className: "chart-section", id: section.key }, [
    element("h2", { textContent: section.title }),
    element("p", { textContent: section.summary }),
    element("p", { className: "machine", textContent: `Measured on ${section.machine}.` }),
    ...section.charts.map(renderChart),
  ]);
}

async function start() {
  const status = $("charts-status");
  let index;
  try {
    const response = await fetch(`${FILES}/index.json`);
    if (response.status === 404) throw new Error("no charts in this build: run `make charts`, then `make web`");
    if (!response.ok) throw new Error(`${FILES}/index.json: HTTP ${response.status}`);
    index = fromJson(schema("ChartIndex"), await response.json());
  } catch (e) {
    status.textContent = `The charts could not be shown: ${e.message}`;
    status.dataset.kind = "error";
    return;
  }
  $("charts").replaceChildren(...index.sections.map(renderSection));
  $("charts-contents").replaceChildren(...index.sections.map((s) =>
    element("a", { href: `#${s.key}`, textContent: `${s.title} (${s.charts.length})` })));
  const count = index.sections.reduce((n, s) => n + s.charts.length, 0);
  status.textContent = `${count} charts in ${index.sections.length} sections.`;
  if (location.hash) document.getElementById(location.hash.slice(1))?.scrollIntoView();
}

window.rtCharts = { ready: start() };
