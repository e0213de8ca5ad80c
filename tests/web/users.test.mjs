// A server with named users (RT_USERS) and quotas, in headless chromium: the
// viewer asks for a token, then shows who is signed in and their use against
// the quotas in the top bar; "Sign out" forgets the token, and the next user
// signs in with theirs and sees only their own scenes.
import assert from "node:assert/strict";
import { join } from "node:path";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, launch, openPage, screenshot } from "./browser.mjs";
import { ROOT, startServer } from "./server.mjs";

const ALICE = "alice-browser-token-0123";
const BOB = "bob-browser-token-012345";
const SCENES = join(ROOT, "build", "scenes");

let server;
let browser;
let page;

describe("signed-in user", { timeout: 90_000 }, () => {
  before(async () => {
    server = await startServer({
      artifacts: ARTIFACTS, samples: false, name: "users", healthToken: ALICE,
      env: { RT_USERS: `alice:${ALICE},bob:${BOB}`, RT_QUOTA_MB: "64", RT_QUOTA_QUEUED_JOBS: "5" },
    });
    browser = await launch();
    page = await openPage(browser, server.url);
    // The first request of each user is refused until the token is given.
    page.expectedProblems.push(/401/);
  });

  after(async () => {
    assert.deepEqual(page?.problems ?? [], [], "no console errors");
    await browser?.close();
    await server?.stop();
  });

  test("the top bar names the user and their use against the quotas", async () => {
    const tokens = [ALICE, BOB];
    const asked = [];
    page.on("dialog", async (dialog) => {
      if (dialog.type() !== "prompt") return dialog.dismiss();
      asked.push(dialog.message());
      await dialog.accept(tokens[asked.length - 1]);
    });
    await page.goto("/");
    await page.waitForFunction(() => document.querySelector("#user-name")?.textContent === "alice", null,
      { timeout: 30_000 });
    assert.equal(asked.length, 1, "asked once");
    assert.equal(await page.textContent("#user-usage"), "0 B stored of 64.0 MB · 0 of 5 jobs queued");
    assert.equal(await page.isVisible("#sign-out"), true);
    await page.setInputFiles("#scene-file", join(SCENES, "teapot.glb"));
    await page.waitForFunction(() => /KB stored of 64\.0 MB/.test(document.querySelector("#user-usage").textContent),
      null, { timeout: 30_000 });
    await screenshot(page, "users-alice");

    await page.click("#sign-out");
    await page.waitForFunction(() => document.querySelector("#user-name")?.textContent === "bob", null,
      { timeout: 30_000 });
    assert.equal(asked.length, 2, "asked again after signing out");
    assert.equal(await page.evaluate(() => localStorage.getItem("rt-api-token")), BOB);
    assert.equal(await page.textContent("#user-usage"), "0 B stored of 64.0 MB · 0 of 5 jobs queued");
    await page.waitForFunction(() => document.querySelector("#scene-list .empty"), null, { timeout: 10_000 });
    await screenshot(page, "users-bob");
  });
});
