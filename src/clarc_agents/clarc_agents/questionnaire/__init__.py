"""Any questionnaire test given by a test definition (definitions/<test>.yaml): the record of a
test and its result, the understanding of an answer, what CLARC says and shows, and the values
orientation is scored against. Pure."""
