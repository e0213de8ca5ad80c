// The Charts page in a real browser: every section and chart of the committed
// chart index (docs/charts/index.json, copied into the build) is shown with its
// picture loaded, its headline and its key figures, the viewer links to it, and
// a narrow window keeps it readable. Screenshots go to test-artifacts/web-charts/.
import assert from "node:assert/strict";
import { mkdirSync, readFileSync, rmSync } from "node:fs";
import { join } from "node:path";
import { after, before, describe, test } from "node:test";
import { launch, openPage } from "./browser.mjs";
import { ROOT, startServer } from "./server.mjs";

const ARTIFACTS = join(ROOT, "test-artifacts", "web-charts");
const INDEX = JSON.parse(readFileSync(join(ROOT, "docs", "charts", "index.json"), "utf8"));

let server;
let browser;
let page;

describe("rt charts page", { timeout: 120_000 }, () => {
  before(async () => {
    rmSync(ARTIFACTS, { recursive: true, force: true });
    mkdirSync(ARTIFACTS, { recursive: true });
    server = await startServer({ artifacts: ARTIFACTS, samples: false });
    browser = await launch();
    page = await openPage(browser, server.url);
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
  });

  test("the committed index has the three sections the issue asks for", () => {
    assert.deepEqual(INDEX.sections.map((s) => s.key), ["speed_accuracy", "stability", "scaling"]);
  });

  test("every chart of the index is shown with its picture, headline and key figures", async () => {
    const response = await page.goto("/charts");
    assert.equal(response.status(), 200);
    await page.evaluate(() => window.rtCharts.ready);
    for (const section of INDEX.sections) {
      const node = page.locator(`section#${section.key}`);
      assert.equal(await node.locator("h2").textContent(), section.title);
      assert.equal(await node.locator("figure.chart").count(), section.charts.length, section.key);
      for (const chart of section.charts) {
        const figure = page.locator(`figure#${chart.slug}`);
        assert.equal(await figure.locator("figcaption").textContent(), chart.headline, chart.slug);
        // Pictures load lazily: bring each into view, then wait for it to decode.
        await figure.locator("img").scrollIntoViewIfNeeded();
        const width = await figure.locator("img").evaluate(async (img) => { await img.decode(); return img.naturalWidth; });
        assert.ok(width > 400, `${chart.slug}.png loaded (${width} px wide)`);
        const rows = chart.table?.rows?.length ?? 0;
        assert.equal(await figure.locator("tbody tr").count(), rows, `${chart.slug} table rows`);
        if (rows) {
          const first = await figure.locator("tbody tr").first().locator("th, td").allTextContents();
          assert.deepEqual(first, chart.table.rows[0].cells, `${chart.slug} first row`);
        }
        const csv = await fetch(`${server.url}/charts/${chart.slug}.csv`);
        assert.equal(csv.status, 200, `${chart.slug}.csv is served`);
      }
    }
    const count = INDEX.sections.reduce((n, s) => n + s.charts.length, 0);
    assert.match(await page.locator("#charts-status").textContent(), new RegExp(`^${count} charts`));
    await page.evaluate(() => window.scrollTo(0, 0));
    await page.screenshot({ path: join(ARTIFACTS, "01-charts.png") });
  });

  test("the viewer's top bar leads to the charts and back", async () => {
    await page.goto("/");
    await page.getByRole("link", { name: "Charts" }).click();
    await page.waitForURL("**/charts");
    await page.getByRole("link", { name: "Viewer" }).click();
    await page.waitForURL((url) => url.pathname === "/");
  });

  test("a narrow window scrolls the tables, not the page", async () => {
    await page.setViewportSize({ width: 420, height: 800 });
    await page.goto("/charts");
    await page.evaluate(() => window.rtCharts.ready);
    const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
    assert.ok(overflow <= 0, `the page is ${overflow} px wider than the window`);
    await page.screenshot({ path: join(ARTIFACTS, "02-charts-narrow.png") });
    await page.setViewportSize({ width: 1280, height: 800 });
  });

  test("no console errors", () => {
    assert.deepEqual(page.problems, []);
  });
});
