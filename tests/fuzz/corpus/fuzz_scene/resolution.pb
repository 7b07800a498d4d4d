"

strawberry*draftHR	{®Gáz„?š™™™™™Ù?