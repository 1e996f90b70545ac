"""Render-farm and cluster sampling: a seed range split into chunks, one `sample` task per chunk
and a final `merge`. Blender-free; the tasks themselves run the add-on's command line."""
