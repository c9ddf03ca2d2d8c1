// Placeholder translation unit so the raytest target exists before its first algorithm lands; delete when raytest/src has real sources.
