"""Cost of one llama_decode with B tokens (probe): is a speculative batch cheap on this CPU?"""
import os, time, ctypes, numpy as np
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
import llama_cpp as L
llm = L.Llama(model_path="/root/.cache/voxposer/models/qwen2.5-coder-1.5b-instruct-q4_k_m.gguf",
              n_ctx=2048, n_batch=512, n_threads=2, n_threads_batch=2, logits_all=False, verbose=False)
text = open("/work/main/src/voxposer/lmp/prompts/" + sorted(os.listdir("/work/main/src/voxposer/lmp/prompts"))[0]).read()[:3000]
toks = llm.tokenize(text.encode(), add_bos=True)[:600]
llm.eval(toks)
n = len(toks)
mem = L.llama_get_memory(llm.ctx)
batch = L.llama_batch_init(16, 0, 1)
def decode(B):
    batch.n_tokens = B
    for i in range(B):
        batch.token[i] = toks[i + 10]; batch.pos[i] = n + i; batch.n_seq_id[i] = 1
        batch.seq_id[i][0] = 0; batch.logits[i] = True
    t = time.perf_counter(); rc = L.llama_decode(llm.ctx, batch); dt = time.perf_counter() - t
    assert rc == 0
    L.llama_memory_seq_rm(mem, 0, n, -1)
    return dt
res = {B: [] for B in (1, 2, 4, 6, 8, 12)}
for rep in range(6):
    for B in res:
        res[B].append(decode(B))
for B, v in res.items():
    print(f"B={B:2d} median {np.median(v)*1e3:6.1f} ms  ratio {np.median(v)/np.median(res[1]):.2f}")
