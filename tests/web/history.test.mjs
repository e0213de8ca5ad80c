// The job history's ✕ (headless chromium against the real service): it asks,
// then deletes a job that has ended with its images, and the entry goes; the
// top bar tells how much the data folder holds; Pin keeps a job from the
// retention policy, and the history says so.
import assert from "node:assert/strict";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, launch, openPage, screenshot } from "./browser.mjs";
import { startServer } from "./server.mjs";

let server;
let browser;
let page;

async function api(path, init) {
  return fetch(`${server.url}${path}`, init);
}

async function renderSmall() {
  const cornell = (await (await api("/api/scenes")).json()).scenes.find((s) => s.name === "cornell.obj");
  let job = await (await api("/api/jobs", { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ scene_id: cornell.id, settings: { width: 32, height: 24 } }) })).json();
  while (job.state !== "DONE") {
    await new Promise((r) => setTimeout(r, 100));
    job = await (await api(`/api/jobs/${job.id}`)).json();
  }
  return job;
}

describe("job history", { timeout: 90_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, name: "history" });
    browser = await launch();
    page = await openPage(browser, server.url);
  });

  after(async () => {
    assert.deepEqual(page?.problems ?? [], [], "no console errors");
    await browser?.close();
    await server?.stop();
  });

  test("a done job is deleted from the history, with its images", async () => {
    const job = await renderSmall();
    await page.goto("/");
    const remove = page.locator(`#history-list button[data-job="${job.id}"]`);
    await remove.waitFor({ timeout: 30_000 });
    assert.equal(await remove.getAttribute("aria-label"), `Delete job ${job.id}`);
    assert.match(await page.textContent("#server-status"), /data [\d.]+ [KMG]?B, [\d.]+ [KMG]?B free/);
    const asked = [];
    page.once("dialog", async (dialog) => {
      asked.push(dialog.message());
      await dialog.dismiss();
    });
    await remove.click();
    await page.waitForTimeout(300);
    assert.equal((await api(`/api/jobs/${job.id}`)).status, 200, "dismissed: nothing deleted");
    page.once("dialog", async (dialog) => {
      asked.push(dialog.message());
      await dialog.accept();
    });
    await remove.click();
    await page.waitForFunction((id) => !document.querySelector(`#history-list button[data-job="${id}"]`), job.id,
      { timeout: 15_000 });
    assert.deepEqual(asked, [`Delete job ${job.id} and its images?`, `Delete job ${job.id} and its images?`]);
    assert.equal((await api(`/api/jobs/${job.id}`)).status, 404);
    assert.equal((await api(`/api/jobs/${job.id}/image.png`)).status, 404);
    await screenshot(page, "history-after-delete");
  });

  test("Pin keeps a job, and the history says so", async () => {
    const job = await renderSmall();
    await page.goto(`/jobs/${job.id}`);
    await page.waitForFunction((id) => window.rt.state.job?.id === id && !document.querySelector("#job-pin").disabled,
      job.id, { timeout: 30_000 });
    assert.equal(await page.getAttribute("#job-pin", "aria-pressed"), "false");
    await page.click("#job-pin");
    await page.waitForFunction(() => document.querySelector("#job-pin").getAttribute("aria-pressed") === "true");
    assert.equal((await (await api(`/api/jobs/${job.id}`)).json()).pinned, true);
    await page.waitForFunction((id) => /pinned/.test(document.querySelector(`small[data-job="${id}"]`)?.textContent),
      job.id, { timeout: 10_000 });
    await page.click("#job-pin");
    await page.waitForFunction(() => document.querySelector("#job-pin").getAttribute("aria-pressed") === "false");
    assert.equal((await (await api(`/api/jobs/${job.id}`)).json()).pinned ?? false, false);
  });
});
