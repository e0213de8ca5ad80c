// Numbers as the viewer shows them.

/** A byte count in B, KB, MB or GB (binary units). */
export function formatBytes(n) {
  const value = Number(n);
  if (value < 1024) return `${value} B`;
  if (value < 1 << 20) return `${(value / 1024).toFixed(0)} KB`;
  if (value < 1 << 30) return `${(value / (1 << 20)).toFixed(1)} MB`;
  return `${(value / (1 << 30)).toFixed(1)} GB`;
}
