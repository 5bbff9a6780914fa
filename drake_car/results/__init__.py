"""Writing results: output folders written all or nothing (``folder``), the one lock
(``lock``), the one atomic writer and the file formats (``files``), how a result was made
(``provenance``) and the Diagram's pictures (``diagram``)."""
