// Placeholder translation unit so the vdb_ref target exists before its first algorithm lands; delete when vdb_ref/src has real sources.
