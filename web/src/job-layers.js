// The linear layers a job has, as the server keeps them: "color"; for a
// denoised job "noisy", its image before denoising; and its auxiliary outputs
// in lower case, with the denoiser's guides (albedo and normal) when it is
// denoised, asked for or not.
import { enumName } from "./proto.js";

export const isDenoised = (job) => enumName("Denoiser", job?.request?.settings?.denoise ?? 0) !== "NO_DENOISER";

export function layerNames(job) {
  const asked = (job.request.outputs ?? []).map((o) => enumName("AuxOutput", o).toLowerCase());
  if (!isDenoised(job)) return ["color", ...asked];
  return ["color", "noisy", ...asked, ...["normal", "albedo"].filter((g) => !asked.includes(g))];
}
